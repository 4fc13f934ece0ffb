// World cache update, direct light (docs/design.md §3 step 5; Solari's
// sample_irradiance, 1st ray): per active cell, RIS over WORLD_CACHE_DI_SAMPLES
// light candidates (target: luminance of the unshadowed irradiance), one
// shadow ray on the winner. WORLD_CACHE_TILE_CANDIDATES 1 (Solari): the
// candidates come from one light tile per workgroup, chosen by the
// workgroup's index alone (v0.18.0:realtime/world_cache_update.wgsl:74-76),
// this frame's tiles or, under 0.17's pass order, last frame's
// (world_cache.light_tiles_frame); 0: drawn afresh as the tiles draw theirs
// (uniform light, triangle, point) with the tiles' radiance encoding. Also
// snapshots the cell's life and root frame before any query of this frame
// changes them (the cache-to-cache queries pass them on). new radiance's w
// is 1 for a cell 0.19's soft cap leaves out of this frame's update.
#version 460
#extension GL_GOOGLE_include_directive : require
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"
#include "core/shared/path_integrator.h"
#include "core/shared/light_tiles.h"
#include "core/shared/reservoir.h"
#include "core/shared/light_sampling.h"
#include "core/shared/restir_di.h"
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/di_bindings.h"

layout(local_size_x = WORLD_CACHE_UPDATE_GROUP) in;
layout(std430, set = 0, binding = BINDING_LIGHT_TILE_PACKED) readonly buffer TilePacked { PackedLightSample tile_packed[]; };

// One candidate: a uniform pick from the workgroup's tile, which starts at
// tile_start (WORLD_CACHE_TILE_CANDIDATES), or a sample drawn afresh.
ResolvedLightSample cache_light_candidate(uint tile_start, INOUT(uint) rng) {
#if WORLD_CACHE_TILE_CANDIDATES != 0
  uint index = tile_start + min(uint(rng_next_float(rng) * float(WORLD_CACHE_TILE_SAMPLES)),
                                uint(WORLD_CACHE_TILE_SAMPLES) - 1u);
  return unpack_light_sample(tile_packed[index], WORLD_CACHE_LIGHT_EXPOSURE, WORLD_CACHE_LOG2_RADIANCE != 0);
#else
  return resolve_light_sample_encoded(generate_light_sample(rng), WORLD_CACHE_LIGHT_EXPOSURE,
                                      WORLD_CACHE_LOG2_RADIANCE != 0);
#endif
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= wc_counters.active_args.w) return;
  uint cell = wc_active[i];
  wc_active_state[i] = uvec2(wc_life[cell], wc_root_frame[cell]);
#if WORLD_CACHE_UPDATE_SOFT_CAP != 0
  // Solari 0.19's soft cap: over it, a cell sits this frame's update out with
  // probability 1 − cap / active. Drawn here once per cell and frame and
  // marked in w, which the GI sample and the blend read.
  uint cap_rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_WORLD_CACHE_SOFT_CAP, wc_checksums[cell],
                          frame.resolution_frame.z);
  if (world_cache_update_skipped(uint(WORLD_CACHE_UPDATE_SOFT_CAP), wc_counters.active_args.w,
                                 rng_next_float(cap_rng))) {
    wc_new_radiance[i] = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
#endif
  vec3 p = wc_geometry[cell].position.xyz;
  vec3 n = wc_geometry[cell].normal.xyz;
  vec3 irradiance = vec3(0.0);
  if (scene_light_count() > 0u) {
    // Streams keyed by the cell's checksum (its identity), not its slot: the same
    // numbers whatever the table size or probing put it.
    uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_WORLD_CACHE_DI, wc_checksums[cell], frame.resolution_frame.z);
    // Solari picks the workgroup's tile by the workgroup index alone, once.
    uint tile_start = 0u;
#if WORLD_CACHE_TILE_CANDIDATES != 0
    tile_start = di_workgroup_tile(uvec2(gl_WorkGroupID.x, 0u), uint(WORLD_CACHE_TILE_COUNT)) *
                 uint(WORLD_CACHE_TILE_SAMPLES);
#endif
    RisStream ris = ris_begin();
    bool chosen = false;
    ResolvedLightSample r;
    for (uint k = 0u; k < uint(WORLD_CACHE_DI_SAMPLES); ++k) {
      ResolvedLightSample candidate = cache_light_candidate(tile_start, rng);
      LightContribution c = light_contribution(candidate, p, n);
      float target = dot(c.wi, n) > 0.0 ? luminance(c.received_radiance) : 0.0;
      float weight = target * c.inverse_pdf / float(WORLD_CACHE_DI_SAMPLES);
      if (ris_update(ris, weight, target, rng_next_float(rng))) {
        chosen = true;
        r = candidate;
      }
    }
    if (chosen) {
      vec3 received = light_contribution(r, p, n).received_radiance;
#if WORLD_CACHE_DROP_ZERO_CHANNEL != 0
      // Bevy keeps the sample only if all(radiance != 0) (world_cache_update.wgsl:101 at
      // v0.18.0): a saturated colour, or a channel rgb9e5 rounds to 0, loses it all.
      if (any(equal(received, vec3(0.0)))) received = vec3(0.0);
#endif
#if WORLD_CACHE_DI_COSINE_MISSING != 0
      // Bevy d458904f56^:realtime/world_cache_update.wgsl:108,122 (#22468 to
      // #22570): the radiance kept has lost the cell's cosine, the target not.
      received /= max(dot(light_contribution(r, p, n).wi, n), 1e-6);
#endif
      if (light_sample_visible(p, n, r)) irradiance = received * ris_contribution_weight(ris);
    }
  }
  wc_new_radiance[i] = vec4(irradiance, 0.0);
}
