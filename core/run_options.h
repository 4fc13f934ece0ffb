// What one run of a scenario is asked to do: the command line's options of
// `giharness run`, as the run engine (replay/run_scenario.h) and the checks
// that read them (the output folder, the seed) see them. A plain description,
// so checks (checks/) read it without reaching the run engine.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

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

}  // namespace gi
