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

#include "core/scenario.h"
#include "replay/checks/check_result.h"

namespace gi {

struct RunOptions {
  std::optional<std::uint32_t> frames;  // --frames
  std::optional<std::uint32_t> seed;    // --seed
  std::optional<int> device;            // --device N
  std::string backend = "auto";         // --backend auto|rayquery|bvh (gpu::BackendRequest)
  std::vector<std::uint32_t> capture;   // --capture, added to the scenario's own
  std::filesystem::path out_dir = "out";
  bool quiet = false;
  std::optional<std::string> profile;   // --profile (name or file), else the scenario's
  std::vector<std::string> sets;        // --set key=value, applied after the scenario's overrides
  // Replay (replay/capture.h): a capture folder; its state is restored and
  // the run continues after its frame.
  std::filesystem::path resume_from;
  // Per-frame hashes of every state buffer to <out>/buffer_hashes.jsonl
  // (also on with captures, resume and the determinism check).
  bool record_hashes = false;
  // Nightly: capture the first failing frame of each failing check (replay/failure_capture.h).
  bool capture_failures = false;
  // summary.json "equal_time": the realtime output beside the GPU and Embree
  // path tracers at its ms/frame (replay/equal_time.h) and its per-signal
  // figures (replay/signal_figures.h), at the last frame the reference check judged.
  bool equal_time = false;
};

struct RunResult {
  int exit_code = 0;  // 0 all checks passed, 1 a check failed (or was inconclusive)
  std::vector<CheckResult> checks;
  nlohmann::json summary;
};

// Throws InputError (exit 2) for bad scenarios and DeviceError (exit 3).
RunResult run_scenario(const Scenario& scenario, const RunOptions& options);


}  // namespace gi
