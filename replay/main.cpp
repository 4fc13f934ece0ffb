// giharness command line (DESIGN §11). Being written; see replay/cli.cpp.
int main() { return 0; }
