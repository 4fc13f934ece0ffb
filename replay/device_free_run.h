// A scenario that one check decides without a device (cluster_ids "count_only",
// a furnace-only scenario): the check's result becomes the run's summary.json
// and exit code, in the same shape run_scenario writes.
#pragma once
#include <chrono>
#include <cstdint>
#include <string>

#include "core/scenario.h"
#include "core/scene.h"
#include "checks/check_result.h"
#include "replay/run_scenario.h"

namespace gi {

// `mode` is the summary's resolved/mode ("count_only", "device_free").
RunResult finish_device_free_run(const Scenario& scenario, const Scene& initial, std::uint32_t frames,
                                 const RunOptions& options, const CheckResult& check, const std::string& mode,
                                 std::chrono::steady_clock::time_point started);

}  // namespace gi
