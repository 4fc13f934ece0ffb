// A check (docs/design.md §6) as the frame loop sees it: one file per check under
// checks/, registered by name (check_registry.h). A check
//   - parses its own parameters when it is made (from a CheckContext);
//   - declares what it needs (CheckNeeds): the inputs it reads each frame,
//     the frames it judges, and what the pipeline must compile or record
//     for it (G-buffer, a second chain, the cache's root frames, hashes);
//   - is shown each judged frame through a FrameView that gives exactly the
//     declared inputs (reading anything else is a programming error);
//   - returns a CheckResult: verdict, figures, limits, first failing frame,
//     evidence.
// The loop (replay/frame_loop.h) compiles and reads back only what some
// check, the capture or the frame record asks for.
#pragma once
#include <array>
#include <filesystem>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/scenario.h"
#include "checks/check_result.h"

namespace gi {

struct Canvas;
struct Profile;
struct RcReference;
struct RcSettings;
struct RealtimeSettings;
struct Scene;
struct FlatGeometry;
struct RunOptions;
namespace gpu {
class Renderer;
struct GiFrameStats;
struct WorldCacheFrameStats;
struct WorldCacheSettings;
}  // namespace gpu

// The world cache's table as a check reads it (FrameInput::cache_cells).
struct CacheCells {
  std::vector<std::uint32_t> checksums, life;
  std::vector<glm::vec4> positions, normals;  // the query point that made each cell, its normal
  const gpu::WorldCacheSettings* settings = nullptr;
};

// What the run computes, fixed before the first frame; a check is made from it.
struct CheckContext {
  const Scenario& scenario;
  const CheckSpec& spec;  // the check's own entry: params and JSON path
  const Profile& profile;
  const RunOptions& options;
  const Scene& initial;   // the scene at frame 0
  std::uint32_t frames = 0, seed = 0;
  bool realtime = false;   // "mode": "realtime"
  bool gi = false;         // ReSTIR GI and specular GI run ("gi": true)
  bool cache_fed = false;  // the world cache runs: GI queries it, or the debug view does
  // A Solari run's profile keys as the run resolved them once
  // (replay/run_setup.h RunSetup::settings); null where the maker has only
  // the profile (a test), and resolved_settings() then resolves it itself.
  const RealtimeSettings* settings = nullptr;
  mutable std::shared_ptr<const RealtimeSettings> resolved_here{};
  const RealtimeSettings& resolved_settings() const;
  // An InputError at the check's JSON path (key empty: the check's "name"):
  // the scenario asks this check for something its run does not compute.
  [[noreturn]] void refuse(const std::string& key, const std::string& why) const;
};

// What a check may read of a frame.
enum class FrameInput {
  output,              // the output's mean luminance and non-finite channels (reduced on the GPU, every frame)
  output_image,        // the output image itself (a full readback: judged frames only)
  gi_stats,            // ReSTIR GI's statistics (integer atomics, gpu/passes/gi_pipeline.h)
  gi_luminance,        // mean luminance of the GI signal (chain A)
  cache_stats,         // the world cache's statistics (gpu/passes/world_cache.h)
  cache_view,          // mean luminance of the debug cache view
  cache_cells,         // the world cache's table: checksums, life, geometry (full readback: judged frames only)
  light_tiles,         // this frame's light-tile samples, chain A (readback: judged frames only)
  cluster_visibility,  // packed visibility IDs and the cluster table
  chains,              // realtime chains A and B: this frame and the window's temporal mean
  gbuffer_layers,      // a layer of chain A's G-buffer (depth, motion, ...; full readback: judged frames only)
  reference_halves,    // the reference mode's two half-sample means
  nonfinite_samples,   // the reference mode's non-finite samples since the window began
  // The radiance-cascades pipeline (replay/rc_run.h):
  rc_canvas,           // the canvas at the frame and the pipeline's settings
  rc_reference,        // the 2D path tracer's image of the frame's canvas (CPU: judged frames only)
};

// A further run of the same scenario that a check compares with the run it
// judges (the determinism check: a second run, a replay from a capture). The
// run engine carries it out after the last frame and before result(), with
// hashes recorded, without the checks that ask for reruns and without any
// capture; a check never starts a run itself.
struct Rerun {
  std::filesystem::path out_subdir;               // under the run's output folder
  std::optional<std::uint32_t> resume_from = {};  // continue from the run's capture of this frame
};

struct CheckNeeds {
  std::set<FrameInput> reads;
  // The frames observe() is called on; none: every frame.
  std::optional<std::set<std::uint32_t>> frames = {};
  bool gbuffer = false;           // the G-buffer (cluster IDs, instance channel)
  // Independent realtime chains the check reads (1: chain A alone); each
  // chain is a pipeline of its own (RunSetup::chains).
  std::uint32_t chains = 1;
  bool cache_root_frame = false;  // the world cache's root-frame instrumentation
  bool gi_temporal_edges = false; // ReSTIR GI's temporal-reuse counts at edge pixels (GiFrameStats)
  bool gi_path_counters = false;  // glossy-path rays and spatial-search outcomes (GiFrameStats::counters)
  bool record_hashes = false;     // per-frame state hashes (buffer_hashes.jsonl)
  std::set<std::uint32_t> captures = {};  // frames captured for the check
  // Realtime accumulation windows start this many frames into each static window.
  std::uint32_t warmup_frames = 0;
  std::vector<Rerun> reruns = {};
};

// One frame as the loop measured it (filled by replay/frame_loop.cpp).
struct FrameData {
  std::uint32_t frame = 0;
  const Scene* scene = nullptr;
  gpu::Renderer* renderer = nullptr;
  // Every chain's pipeline, chain A's (`renderer`) first (RunSetup::chains).
  std::vector<const gpu::Renderer*> chains;
  std::uint32_t window_start = 0;    // first frame of the accumulation window
  std::uint64_t window_samples = 0;  // samples per pixel accumulated in it
  // The output image: `output` where the caller has it, else read_output
  // reads it back (once per frame; only a check that asks pays for it).
  const Image* output = nullptr;
  std::function<const Image&()> read_output;
  double output_luminance = 0.0;
  std::uint64_t nonfinite_pixels = 0;
  std::uint64_t nonfinite_samples = 0;  // reference mode: since the window began
  const gpu::GiFrameStats* gi_stats = nullptr;             // null without GI
  double gi_luminance = 0.0;
  const gpu::WorldCacheFrameStats* cache_stats = nullptr;  // null without the world cache
  std::optional<double> cache_view_luminance;              // with the debug view
  // The radiance-cascades pipeline's frame (null for Solari's).
  const Canvas* rc_canvas = nullptr;
  const RcSettings* rc_settings = nullptr;
  std::function<const RcReference&()> rc_reference;  // computed on first call, shared by the checks
};

// A check's window on one frame: the declared inputs, nothing else.
class FrameView {
 public:
  FrameView(const FrameData& data, const std::set<FrameInput>& allowed) : data_(data), allowed_(allowed) {}
  std::uint32_t frame() const { return data_.frame; }
  const Scene& scene() const { return *data_.scene; }
  std::uint32_t window_start() const { return data_.window_start; }
  std::uint64_t window_samples() const { return data_.window_samples; }

  const Image& output() const;
  double output_luminance() const;
  std::uint64_t nonfinite_pixels() const;
  const gpu::GiFrameStats* gi_stats() const;  // null without GI
  double gi_luminance() const;
  const gpu::WorldCacheFrameStats* cache_stats() const;  // null without the world cache
  std::optional<double> cache_view_luminance() const;    // none without the debug view
  // The world cache's table, read back now (call it only on the frames the
  // check judges: it downloads every cell).
  CacheCells cache_cells() const;
  // This frame's light-tile samples of chain A, tile-major, and the samples
  // per tile (read back now: call it on judged frames only).
  std::vector<std::array<std::uint32_t, 4>> light_tile_samples(std::uint32_t& samples_per_tile) const;
  std::vector<glm::uvec2> packed_visibility() const;
  const std::vector<std::uint32_t>& cluster_table() const;
  // Realtime: DI, plus GI and specular when they run, of chain 0 .. chain_count()-1
  // (pipelines that share no state, RunSetup::chains).
  std::uint32_t chain_count() const;
  Image chain_frame(std::uint32_t chain) const;
  Image chain_mean(std::uint32_t chain) const;
  std::uint32_t chain_window_frames() const;  // frames in chain A's temporal mean
  bool full_gi() const;                       // the chains' images include GI and specular
  Image reference_half(int which) const;
  // A G-buffer layer by name (gpu::Renderer::gbuffer_layer_names()).
  Image gbuffer_layer(const std::string& name) const;
  std::uint64_t nonfinite_samples() const;
  // Radiance cascades: the canvas at this frame, the settings, the reference.
  const Canvas& rc_canvas() const;
  const RcSettings& rc_settings() const;
  const RcReference& rc_reference() const;

 private:
  void require(FrameInput input, const char* what) const;
  const gpu::Renderer& chain_pipeline(std::uint32_t chain) const;
  const FrameData& data_;
  const std::set<FrameInput>& allowed_;
};

class Check {
 public:
  virtual ~Check() = default;
  virtual CheckNeeds needs() const = 0;
  // After the renderer is built or rebuilt, and after its geometry changes.
  virtual void prepare(gpu::Renderer& /*renderer*/, const Scene& /*scene*/, const FlatGeometry& /*geometry*/) {}
  // A judged frame; `record` is the frame's line in frames.jsonl, where the
  // check may add its per-frame figures.
  virtual void observe(const FrameView& frame, nlohmann::json& record) = 0;
  // State carried through a capture, so a replay's verdict covers the frames
  // before the snapshot too (null: none).
  virtual nlohmann::json saved_state() const { return nullptr; }
  virtual void restore_state(const nlohmann::json& /*state*/) {}
  // After the last frame (and after the run's hash log is complete).
  virtual CheckResult result() = 0;
  // A check that decides without drawing anything (cluster_ids "count_only",
  // a scenario of one furnace check) names the mode the run's summary
  // records; the run engine then opens no device, draws nothing and takes
  // result() as the run's verdict.
  virtual std::optional<std::string> decides_alone() const { return std::nullopt; }
};

}  // namespace gi
