// The world cache (docs/design.md §3 step 5) as the Renderer drives it: owns the
// spatial hash's buffers and its passes, one GLSL file each under
// gpu/shaders/world_cache_*.comp:
//   decay → compact (count, scan, write: the active list and an indirect
//   dispatch) → sample_di → sample_gi (cache-to-cache queries) → commit →
//   blend → [query_pixels: the cache view, debug only] → the pixel-rooted
//   commit (GI's, specular GI's and the view's insertions) → stats.
// Insertions are deterministic: a query that finds an empty slot claims it
// with atomicMin of its id and leaves a record; the commit pass writes the
// lowest id's record (README, "World cache").
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "core/shared/world_cache.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/host_mirror.h"
#include "gpu/shader_compiler.h"
#include "gpu/state_buffers.h"
#include "gpu/timer.h"

namespace gi::gpu {

// Every constant from the profile (world_cache.*, light_tiles.* for the radiance
// encoding and the tiles, brdf.* and specular.* for the secondary hits), filled
// by the profile table (gpu/profile_keys.cpp): a profile-filled field has no
// value of its own here (value-initialised; every value is the profile's). The
// run's own fields (view, stats, root_frame, external_queries_per_pixel) keep theirs.
struct WorldCacheSettings {
  std::uint32_t cells{};       // power of two, ≥ WORLD_CACHE_SCAN_BLOCK
  std::uint32_t lifetime{};
  std::uint32_t max_probe_steps{};
  bool linear_probing{};           // false: re-hash (0.17)
  float cell_size_base{};
  float lod_scale{};
  // Solari 0.19's query (v0.19.0:realtime/world_cache_query.wgsl:43-112) and
  // update: the LOD drawn between two sizes, the query point jittered in the
  // tangent plane, the normal keyed at half-unit steps, ReSTIR GI's short
  // first-bounce rays querying a base cell, a soft cap on the cells updated
  // a frame (0: none).
  bool stochastic_lod{};
  bool jitter{};
  // world_cache.jitter_lod "redrawn": the cell size is drawn again at the
  // jittered point (v0.18.0 world_cache_query.wgsl:58, v0.19.0 :60); "kept"
  // quantizes the moved point with the size of the unmoved one (#21649's
  // jitter before #21953 fixed it: cells keyed at an LOD their point does not have).
  bool jitter_lod_redrawn{};
  float normal_key_scale{};
  bool first_bounce_leak_rule{};
  std::uint32_t update_soft_cap{};
  // world_cache.workgroup_size: the width of the per-active-cell passes'
  // workgroups (sample_di, sample_gi, blend; 1024 in 0.17, 64 since). Cells
  // are independent, so it changes speed, not results.
  std::uint32_t update_workgroup_size{};
  bool cache_to_cache_full{};     // true: 0.17's lifetime rule
  bool adaptive_blend{};           // false: 0.17's fixed blend
  float max_samples{};
  float adaptive_exponent{};
  float delta_blend{};
  std::uint32_t di_samples{};
  float gi_ray_tmax{};
  // world_cache.gi_ray_direction "unnormalised" (0.17, 0.18): the GI ray's
  // reach is gi_ray_tmax times 2 cos of its angle to the cell's normal.
  bool gi_reach_cosine{};
  float light_exposure{};
  bool log2_radiance{};
  // brdf.secondary_hits "full": a cell's GI ray that hits a glossy surface
  // (alpha ≤ glossy_roughness) follows it along its BRDF for up to
  // glossy_bounces vertices (specular.*) before querying the cache; false:
  // Solari's diffuse-only cache (hit_radiance.glsl).
  bool secondary_hits_full{};
  bool secondary_albedo_base{};  // brdf.secondary_albedo (GiSettings)
  bool hit_normal_vertex{};      // world_cache.hit_normal (GiSettings::hit_cache_normal_vertex)
  // world_cache.direct_light_zero_channel "drop": a cell's direct light is
  // lost when any channel of the chosen sample's radiance is 0 (Bevy 0.17-0.19:
  // a pure red light never lights the cache).
  bool drop_zero_channel_light{};
  // world_cache.direct_light_cosine "missing" (Bevy #22468 to #22570,
  // unreleased): the chosen light sample's radiance is kept without the
  // cell's cosine, which the RIS target has: direct light divided by n.l.
  bool direct_light_cosine_missing{};
  // light_tiles.sun_sampling "center" (DiSettings::sun_center), for the
  // candidates the cache draws itself.
  bool sun_center{};
  // world_cache.direct_light_candidates "light_tiles" (Solari): the direct-light
  // candidates come from one light tile per workgroup (DI's tiles, chain 0:
  // tile_count × tile_samples); false: drawn afresh by the cache itself.
  bool tile_candidates{};
  // light_tiles.tile_count and .samples_per_tile; the Renderer replaces them
  // with DI's tiles as sized to the scene when tile_candidates.
  std::uint32_t tile_count{};
  std::uint32_t tile_samples{};
  // world_cache.light_tiles_frame "previous" (0.17's pass order, cache before
  // tiles): the update runs before DI rebuilds the tiles, so it reads last
  // frame's (Renderer::render_frame). Only with tile_candidates.
  bool tiles_previous_frame{};
  float glossy_roughness{};
  std::uint32_t glossy_bounces{};
  // The cache view (world_cache_query_pixels): a pixel-rooted query at every
  // primary surface each frame. Bevy makes that query only under the debug
  // define VISUALIZE_WORLD_CACHE (v0.17.0:realtime/restir_gi.wgsl:85,
  // v0.18.0:realtime/specular_gi.wgsl:75); its queries keep cells alive and
  // add cells no GI ray touches, so it is off unless a scenario asks
  // ("cache_view": true). Otherwise GI's and specular GI's queries alone feed it.
  bool view = false;
  bool stats = false;       // the per-frame statistics pass (blend_lag, cache_lifetime)
  bool root_frame = false;  // root-frame instrumentation (cache_lifetime): WORLD_CACHE_ROOT_FRAME
  // Pixel-rooted queries per pixel that other passes add to the cache's own
  // (ReSTIR GI and specular GI with restir_gi.hit_radiance "world_cache": 2 per
  // chain); sizes the pending list only.
  std::uint32_t external_queries_per_pixel = 0;

  std::vector<ShaderDefine> defines(std::uint32_t pending_capacity) const;
};

// One frame's statistics (settings.stats), read after render.
struct WorldCacheFrameStats {
  std::uint32_t active_cells = 0;      // cells this frame's update could sample (life > 0 at its start)
  std::uint32_t updated_cells = 0;     // of those, the ones it blended (all but 0.19's soft cap's)
  std::uint32_t live_cells = 0;        // at the end of the frame
  std::uint32_t sampled_cells = 0;
  double mean_radiance = 0.0;          // mean luminance of the sampled cells' irradiance
  std::uint32_t over_age_cells = 0;    // root-frame instrumentation only
  std::uint32_t oldest_age = 0;
  std::uint32_t life_out_of_range = 0;
  std::uint32_t dead_not_empty = 0;
  std::uint32_t nonfinite_cells = 0;
};

class WorldCache {
 public:
  WorldCache(Device& device, ShaderCompiler& compiler, const WorldCacheSettings& settings, std::uint32_t width,
             std::uint32_t height);

  // light_tiles: DI's packed tiles (DiPipeline::tile_packed), read when
  // settings().tile_candidates; null binds a placeholder.
  void bind(const SceneResources& scene, const Buffer& gbuffer, const Buffer* light_tiles = nullptr);
  // Records every pass with barriers; timed as world_cache_decay,
  // world_cache_compact, world_cache_sample_di, world_cache_sample_gi (with its
  // commit), world_cache_blend, world_cache_view (settings.view only),
  // world_cache_commit and world_cache_stats.
  void record(VkCommandBuffer cmd, GpuTimer& timer);
  // The same frame in two halves, for passes that query the cache in between
  // (ReSTIR GI, specular GI): record_update runs decay .. blend and the cache
  // view's queries, record_commit the pixel-rooted commit (the view's and the
  // other passes' insertions, lowest query id per slot) and the statistics.
  // Queries in between read this
  // frame's blended radiance and must use the pixel-rooted list (1) with ids
  // from width·height up (the view's are the pixel indices).
  void record_update(VkCommandBuffer cmd, GpuTimer& timer);
  void record_commit(VkCommandBuffer cmd, GpuTimer& timer);
  // Every cache buffer by binding number (world_cache_bindings.h), for another
  // pass that includes world_cache_common.glsl; and the defines it compiles with.
  std::vector<std::pair<std::uint32_t, const Buffer*>> buffer_table() const;
  std::vector<ShaderDefine> shader_defines() const { return settings_.defines(pending_capacity_); }

  // The statistics as record_readbacks copied them (the end of the frame).
  WorldCacheFrameStats stats() const;
  // At the end of the frame's command buffer: counters and statistics copied for the host.
  void record_readbacks(VkCommandBuffer cmd) const;
  Image view() const;  // irradiance at each pixel's primary surface, from the cache (settings.view)
  // Persistent buffers: checksums, life, radiance, luminance delta, geometry, root frame.
  void list_state(StateList& out);
  const WorldCacheSettings& settings() const { return settings_; }

  std::vector<std::uint32_t> checksums() const { return checksums_.download<std::uint32_t>(settings_.cells); }
  std::vector<std::uint32_t> life() const { return life_.download<std::uint32_t>(settings_.cells); }
  std::vector<glm::vec4> radiance() const { return radiance_.download<glm::vec4>(settings_.cells); }
  std::vector<std::uint32_t> root_frames() const { return root_frame_.download<std::uint32_t>(settings_.cells); }
  std::vector<shader::WorldCacheGeometry> geometry() const {
    return geometry_.download<shader::WorldCacheGeometry>(settings_.cells);
  }

 private:
  void commit_pixel_queries(VkCommandBuffer cmd);
  void record_stats(VkCommandBuffer cmd, GpuTimer& timer);

  WorldCacheSettings settings_;
  std::uint32_t width_, height_;
  std::uint32_t pending_capacity_;
  Buffer checksums_, life_, radiance_, delta_, geometry_, root_frame_;
  Buffer claims_, active_, active_state_, new_radiance_, block_sums_, counters_, pending_, stats_, view_;
  ComputePass decay_, compact_scan_, compact_write_, sample_di_, sample_gi_, pending_args_,
      commit_, blend_, stats_pass_;
  std::optional<ComputePass> query_pixels_;  // settings.view only
  HostMirror counters_host_, stats_host_;
};

}  // namespace gi::gpu
