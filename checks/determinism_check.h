// The `determinism` check (docs/design.md §6) and `replay --verify`: per-frame hashes
// of every buffer Renderer::list_state gives (<out>/buffer_hashes.jsonl, one
// {"frame", "buffers": [[name, hash], …]} a line), compared frame by frame
// and buffer by buffer; the first divergent frame and its buffers are named.
//
// The check asks the run engine for two more runs of the scenario after the
// main run (CheckNeeds::reruns): a second run from frame 0, and a replay from
// the snapshot the main run captured at `snapshot_frame` (default frames / 2).
// Both must match the main run bit for bit.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "checks/check_result.h"
#include "checks/check.h"

namespace gi {

struct Divergence {
  std::uint32_t frame = 0;
  std::vector<std::string> buffers;  // in list order; "name (missing)" for a buffer only one side has
};

struct HashLogComparison {
  std::uint64_t frames_compared = 0;   // frames both logs hold
  std::uint64_t divergent_frames = 0;
  std::uint64_t unmatched_frames = 0;  // candidate frames the original has no record of
  std::optional<Divergence> first;

  bool identical() const { return frames_compared > 0 && divergent_frames == 0; }
  std::string describe() const;  // one line: "frame 61: di/stored_reservoirs, di/output differ" or "… identical"
  nlohmann::json to_json() const;
};

// buffer_hashes.jsonl → comparison of `candidate` against `original`.
// Unreadable or malformed logs are gi::InputError naming the file and line.
HashLogComparison compare_hash_logs(const std::filesystem::path& original, const std::filesystem::path& candidate);

struct DeterminismParams {
  bool second_run = true;
  std::optional<std::uint32_t> snapshot_frame;  // none: no replay from a snapshot
};

// Validates the check's parameters: "second_run" (bool), "snapshot_frame"
// (a frame below frames − 1, or null for none; default frames / 2).
DeterminismParams determinism_params(const CheckSpec& spec, const Scenario& scenario, std::uint32_t frames);

// The reruns the check asks for: <out>/determinism/second_run, and
// <out>/determinism/replay resumed from the snapshot frame's capture.
std::vector<Rerun> determinism_reruns(const DeterminismParams& params);

// After the main run (which recorded its hashes and captured the snapshot
// frame) and the reruns: compares each rerun's hash log under `out_dir` with
// the main run's.
CheckResult judge_determinism(const std::filesystem::path& out_dir, const DeterminismParams& params);

}  // namespace gi
