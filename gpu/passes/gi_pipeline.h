// ReSTIR GI and specular GI as the Renderer drives them (docs/design.md §3 steps 7-8):
// owns the GI reservoirs, last frame's surfaces, the outputs and sums of
// `chains` independent chains (as DiPipeline: two chains are two honest
// halves for the reference check), and the per-frame statistics buffer the
// `jacobian` and `finite` checks read (integer atomics; 160 bytes a frame).
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "core/image.h"
#include "core/shared/restir_gi.h"
#include "gpu/buffer.h"
#include "gpu/host_mirror.h"
#include "gpu/passes/restir_gi.h"
#include "gpu/passes/specular_gi.h"
#include "gpu/passes/world_cache.h"
#include "gpu/state_buffers.h"
#include "gpu/timer.h"

namespace gi::gpu {

// One frame's GiStats (core/shared/restir_gi.h), read back after the frame.
struct GiFrameStats {
  std::uint32_t merges = 0, rejections = 0;
  float max_accepted_j = 0.0f;
  std::uint32_t nonfinite_jacobians = 0, nonfinite_reservoirs = 0, nonfinite_output = 0;
  // With GiSettings::temporal_edge_stats: chain A's edge pixels that had an
  // on-screen history, and those whose temporal reuse found it usable.
  std::uint32_t temporal_edge_pixels = 0, temporal_edge_reused = 0;
  std::vector<std::uint32_t> log2_j_histogram;
  // With GiSettings::path_counters (chain A): glossy paths and their
  // closest-hit rays; pixels that sought a spatial neighbour, and found one.
  std::optional<shader::GiCounters> counters;  // bin b: 2^(b−16) ≤ J < 2^(b−15); bin 0 holds J = 0
};

class GiPipeline {
 public:
  GiPipeline(Device& device, ShaderCompiler& compiler, const GiSettings& settings, std::uint32_t width,
             std::uint32_t height);

  // world_cache: the cache the passes query (settings.queries_world_cache()).
  void bind(const SceneResources& scene, const Buffer& gbuffer, const WorldCache* world_cache = nullptr);
  // This frame's GI and specular signals: vec4 per pixel, chain-major.
  const Buffer& output_buffer() const { return output_; }
  const Buffer& specular_output_buffer() const { return specular_output_; }
  // Records gi_initial_temporal, gi_spatial_shade and (settings.specular)
  // specular_gi, each timed, with barriers. Zeroes the statistics first.
  void record(VkCommandBuffer cmd, GpuTimer& timer, bool accumulate, std::uint32_t frame_index, std::uint32_t seed);
  void reset_accumulation();

  Image gi_frame(std::uint32_t chain) const;
  Image gi_mean(std::uint32_t chain) const;
  Image specular_frame(std::uint32_t chain) const;  // zeros when specular is off
  Image specular_mean(std::uint32_t chain) const;
  // The statistics as record_readbacks copied them (the end of the frame).
  GiFrameStats stats() const;
  // At the end of the frame's command buffer: the statistics' copy for the host.
  void record_readbacks(VkCommandBuffer cmd) const {
    stats_host_.record_copy(cmd);
    if (counters_host_) counters_host_->record_copy(cmd);
  }
  const GiSettings& settings() const { return settings_; }

  void list_state(StateList& out);
  void save_host_state(HostState& out) const;
  void restore_host_state(const HostState& in);

 private:
  std::size_t pixels() const { return std::size_t(width_) * height_; }
  Image channel(const Buffer& buffer, std::uint32_t chain, bool mean) const;

  GiSettings settings_;
  std::uint32_t width_, height_;
  Buffer stored_, mid_, surfaces_, output_, accumulation_, stats_, specular_output_, specular_accumulation_;
  Buffer history_;  // restir_gi.temporal_history "temporal" (else one unused slot)
  GiInitialTemporal initial_temporal_;
  GiSpatialShade spatial_shade_;
  std::optional<SpecularGi> specular_;
  HostMirror stats_host_;
  Buffer counters_;  // GiCounters with settings.path_counters (else one unused word)
  std::optional<HostMirror> counters_host_;
  bool history_valid_ = false;
};

}  // namespace gi::gpu
