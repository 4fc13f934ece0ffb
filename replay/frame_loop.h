// The second part of a run (replay/run_scenario.h): the frames. Per frame it
// applies the scenario's events, renders, reads back what the frame record,
// the noise figures, the captures and the checks need (each check through a
// FrameView of what it declared), and records hashes and captures. A resumed
// run (RunOptions::resume_from) rebuilds the pipeline at the captured frame
// and restores its state, the loop's and the checks' first.
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/cpu_schedule.h"
#include "core/image.h"
#include "core/scene.h"
#include "core/scene_flatten.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "replay/frame_log.h"
#include "replay/run_setup.h"
#include "replay/signal_noise.h"

namespace gi {

class FrameLoop {
 public:
  FrameLoop(const Scenario& scenario, const RunOptions& options, RunSetup& setup, gpu::Device& device);
  // Frames first_frame() .. frames-1; finishes the hash log.
  void run();

  std::uint32_t first_frame() const { return first_frame_; }
  const Image& last_output() const { return output_; }  // after run(): the last frame's
  const gpu::Renderer& renderer() const { return *renderer_; }
  // Chain c's pipeline (0: renderer(); RunSetup::chains of them).
  const gpu::Renderer& chain_pipeline(std::uint32_t chain) const {
    return chain == 0 ? *renderer_ : *other_chains_.at(chain - 1);
  }
  gpu::ShaderCompiler& compiler() { return compiler_; }
  std::size_t light_count() const { return flat_.lights.size(); }
  FrameLog& frame_log() { return frame_log_; }
  bool hash_log_written() const { return hash_log_.has_value(); }
  const std::vector<std::uint32_t>& captured_frames() const { return captured_frames_; }
  // summary.json's "noise": per-frame chain noise and temporal noise (realtime).
  nlohmann::json noise() const { return noise_; }
  // What a baseline holds to be exact (reports/change.h): the output image's
  // hash per frame (from first_frame()), and every state buffer's hash after
  // the last frame (one readback of the state, at the end only).
  const std::vector<std::string>& frame_image_hashes() const { return frame_image_hashes_; }
  // Host wall time of each frame's whole iteration (events, rendering, record,
  // checks, hashes, captures), ms: what observing costs beside the GPU time.
  const std::vector<double>& frame_wall_ms() const { return frame_wall_ms_; }
  const nlohmann::json& final_state_hashes() const { return final_state_hashes_; }

 private:
  void build_renderer();  // the renderer for geometry_, the checks prepared, scene_'s instances uploaded
  void upload_scene();    // flat_ from scene_ as the profile's renderer sees it, uploaded
  // Both pipelines (chain B's when it runs): what every frame's events do to them.
  template <typename F>
  void each_pipeline(F&& f) {
    f(*renderer_);
    for (auto& chain : other_chains_) f(*chain);
  }

  void resume();
  void apply_frame_events(std::uint32_t frame);
  // One frame's results the record and the checks read, taken right after
  // its submission finished (small: the GPU reduced them).
  struct Taken {
    std::uint32_t frame = 0;
    std::chrono::steady_clock::time_point started;
    std::uint32_t window_start = 0;
    std::uint64_t window_samples = 0;
    std::vector<gpu::PassTiming> timings;
    double calibration_ms = 0.0;  // the calibration kernel's time (CPU devices)
    CpuSchedule cpu;              // this process's CPU run and wait, submission to finish (CPU devices)
    gpu::FrameMeasures measures;
    std::uint64_t nonfinite_samples = 0;
    std::optional<gpu::GiFrameStats> gi_stats;
    std::optional<gpu::WorldCacheFrameStats> cache_stats;
    std::vector<std::string> state_hashes;  // hash-log frames and the last
    gpu::Device::TransferCounts transfers;  // moved by the frame's rendering and take()
  };
  Taken take(std::uint32_t frame, std::chrono::steady_clock::time_point started,
             const gpu::Device::TransferCounts& before);
  bool can_defer(std::uint32_t frame) const;
  bool logs_hashes(std::uint32_t frame) const;    // the hash log records this frame
  bool hashes_state(std::uint32_t frame) const;  // the log's frames and the last (the summary's hashes)
  void observe(const Taken& taken, bool deferred);
  const Image& read_output();  // this frame's output image, read back once
  std::uint32_t noise_start() const { return std::max(first_frame_, setup_.frames / 2); }
  static double since_ms(std::chrono::steady_clock::time_point from, std::chrono::steady_clock::time_point to) {
    return std::chrono::duration<double, std::milli>(to - from).count();
  }
  void capture(std::uint32_t frame);
  nlohmann::json chain_noise_figures(std::uint32_t frame) const;
  nlohmann::json restored_state_hashes(std::uint32_t frame);  // hashed now, in a submission of their own

  const Scenario& scenario_;
  const RunOptions& options_;
  RunSetup& setup_;
  gpu::Device& device_;
  gpu::ShaderCompiler compiler_;
  Scene scene_;
  FlatGeometry geometry_;
  FlatInstances flat_;
  std::unique_ptr<gpu::Renderer> renderer_;
  // Chains 1 .. RunSetup::chains-1: pipelines of their own at
  // independent_chain_seed, fed the same scene and events; only the checks'
  // chain images, the chain noise figures and captures read them.
  std::vector<std::unique_ptr<gpu::Renderer>> other_chains_;

  // The accumulation window (reference mode; realtime temporal means).
  std::uint64_t window_samples_ = 0;
  std::uint32_t window_start_ = 0;  // first frame of the accumulated estimate
  std::uint32_t static_start_ = 0;  // last frame the scene changed
  std::uint32_t first_frame_ = 0;
  GpuCamera previous_camera_{};
  Image output_;                    // this frame's output, when read back (output_read_)
  bool output_read_ = false;

  FrameLog frame_log_;
  std::optional<FrameLog> hash_log_;
  TemporalNoise temporal_noise_;
  nlohmann::json noise_ = nullptr;
  std::vector<std::uint32_t> captured_frames_;
  std::vector<std::string> frame_image_hashes_;
  std::vector<double> frame_wall_ms_;
  nlohmann::json final_state_hashes_ = nlohmann::json::object();
};

}  // namespace gi
