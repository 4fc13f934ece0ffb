// libFuzzer entry point for scenario files (see fuzz_targets.h).
#include "tests/fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gi::fuzz::scenario_input(data, size);
  return 0;
}
