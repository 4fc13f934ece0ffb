// giharness command line (docs/design.md §11). Exit codes: 0 all checks passed,
// 1 a check failed or a regression was found, 2 bad input, 3 no usable device
// or an internal error.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>
#include <spdlog/cfg/env.h>
#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "app/commands.h"

int main(int argc, char** argv) {
  spdlog::cfg::load_env_levels();  // SPDLOG_LEVEL=debug: e.g. each pipeline's driver compile time
  CLI::App app{"giharness: deterministic validation harness for real-time ray-traced GI"};
  app.require_subcommand(1);
  gi::Commands commands;
  commands.add_to(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;  // a malformed command line is bad input
  }
  try {
    return commands.execute();
  } catch (const gi::InputError& e) {
    std::fprintf(stderr, "giharness: bad input: %s\n", e.what());
    return 2;
  } catch (const gi::DataDirError& e) {
    std::fprintf(stderr, "giharness: %s\n", e.what());  // names the data folder itself
    return 3;
  } catch (const gi::DeviceError& e) {
    std::fprintf(stderr, "giharness: device error: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "giharness: internal error: %s\n", e.what());
    return 3;
  }
}
