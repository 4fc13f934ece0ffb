// The subcommands: options are bound to CLI11 here; each command's work lives
// in its own file (run_scenario.cpp, reference_command.cpp, nightly.cpp).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "replay/run_scenario.h"

namespace gi {

struct ReferenceCommandOptions {
  std::filesystem::path scenario;
  std::optional<std::uint32_t> spp;
  std::optional<std::uint32_t> frame;
  unsigned threads = 0;
  std::filesystem::path out_dir = "out/reference";
};

struct NightlyOptions {
  std::filesystem::path suite = "scenarios";
  std::filesystem::path out_dir = "out/nightly";
  std::optional<int> device;
};

int run_reference_command(const ReferenceCommandOptions& options);
int run_nightly(const NightlyOptions& options);
int list_devices_command();

class Commands {
 public:
  void add_to(CLI::App& app);
  int execute();

 private:
  CLI::App* run_ = nullptr;
  CLI::App* reference_ = nullptr;
  CLI::App* nightly_ = nullptr;
  CLI::App* devices_ = nullptr;
  std::filesystem::path scenario_path_;
  RunOptions run_options_;
  std::string capture_list_;
  ReferenceCommandOptions reference_options_;
  NightlyOptions nightly_options_;
};

}  // namespace gi
