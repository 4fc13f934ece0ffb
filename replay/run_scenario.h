// Runs one scenario end to end: build the scene, drive the GPU pipeline frame
// by frame applying the scenario's events, record what the checks need, run
// the checks, write summary.json and the requested captures.
#pragma once
#include "core/cache_root.h"  // cache_root(), for the commands that include this header
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/run_options.h"
#include "core/scenario.h"
#include "checks/check_result.h"

namespace gi {


struct RunResult {
  int exit_code = 0;  // 0 all checks passed, 1 a check failed (or was inconclusive)
  std::vector<CheckResult> checks;
  nlohmann::json summary;
};

// Throws InputError (exit 2) for bad scenarios and DeviceError (exit 3).
RunResult run_scenario(const Scenario& scenario, const RunOptions& options);


}  // namespace gi
