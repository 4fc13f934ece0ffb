// Nightly: a failing check always leaves a capture of its first failing
// frame. The failure is known only when the check is judged (often at the
// end), so the scenario is run again, bit-identically (docs/design.md §6), with those
// frames captured; the capture folders are moved into the run's captures/.
#pragma once
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "checks/check_result.h"
#include "replay/run_scenario.h"

namespace gi {

// For each failing check: its first failing frame (the last frame when it
// names none). Frames the run already captured are only listed. Adds the
// capture folder to each check's evidence; returns
// [{"check", "frame", "capture"}] for summary.json, with the check's
// "region" and "region_mask" where it judged a region (CheckResult::region).
nlohmann::json capture_failing_frames(const Scenario& scenario, const RunOptions& run, std::uint32_t frames,
                                      const std::vector<std::uint32_t>& captured, std::vector<CheckResult>& checks);

}  // namespace gi
