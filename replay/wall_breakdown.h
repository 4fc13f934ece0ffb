// A run's wall time by phase (core/phase_clock.h) for summary.json's
// "wall_breakdown", with an estimate of the driver's shader compile at first
// dispatch: lavapipe compiles a pipeline with LLVM when it first runs, inside
// the frame's GPU work, so that time shows as frame 0's pass time above the
// pass's later frames. The nightly adds the runs' breakdowns up.
#pragma once
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace gi {

// wall_seconds: the run's; frames: summary.json's per-frame records (each
// with "frame" and "pass_ms"), the first of them the run's first frame;
// phases_at_start: phase_seconds() when the run began (a process may run
// several scenarios: run --seeds, sweep, the determinism check's rerun).
nlohmann::json wall_breakdown(double wall_seconds, const nlohmann::json& frames,
                              const std::map<std::string, double>& phases_at_start = {});

// Adds one run's breakdown to a total of the same form (a null total: none yet).
void add_wall_breakdown(nlohmann::json& total, const nlohmann::json& run);

// One line for the log: "wall 35.0 s: frames 20.1 s (first-dispatch compile ≈ 12.0 s), ...".
std::string wall_breakdown_line(const nlohmann::json& breakdown);

}  // namespace gi
