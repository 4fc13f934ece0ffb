// The last part of a run (replay/run_scenario.h): summary.json, written
// atomically into the out dir. Its keys are documented in README
// "Command line" and read by the nightly suite, baselines and reports.
#pragma once
#include <chrono>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "replay/frame_loop.h"
#include "replay/run_setup.h"

namespace gi {

struct RunFacts {
  const Scenario& scenario;
  const RunOptions& options;
  const RunSetup& setup;
  FrameLoop& loop;
  gpu::Device& device;
  std::chrono::steady_clock::time_point started;
  std::map<std::string, double> phases_at_start;  // phase_seconds() then: a process may run many scenarios
  std::size_t references_at_start = 0;            // reference_entries_used().size() then
};

// summary.json's "timings" (per pass, and per frame: the GPU pass sum and the
// host's wall time), "frames" (the log's kept records) and "frames_log";
// finishes the log. The radiance-cascades run (replay/rc_run.h) shares it.
void add_frames(FrameLog& log, const std::vector<double>& frame_wall_ms, nlohmann::json& s);

// Fills result.summary from the run and result.checks, and writes it.
void write_run_summary(const RunFacts& run, const nlohmann::json& failure_captures, RunResult& result);

}  // namespace gi
