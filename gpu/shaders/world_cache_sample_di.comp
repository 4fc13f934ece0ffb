// World cache update, direct light (DESIGN §3 step 5; Solari's
// sample_irradiance, 1st ray): per active cell, RIS over WORLD_CACHE_DI_SAMPLES
// light candidates (target: luminance of the unshadowed irradiance), one
// shadow ray on the winner. Candidates are drawn as the light tiles draw theirs
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
#include "gpu/shaders/world_cache_common.glsl"

layout(local_size_x = WORLD_CACHE_UPDATE_GROUP) in;

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
    RisStream ris = ris_begin();
    LightSample chosen;
    chosen.valid = 0u;
    for (uint k = 0u; k < uint(WORLD_CACHE_DI_SAMPLES); ++k) {
      LightSample s = generate_light_sample(rng);
      ResolvedLightSample r = resolve_light_sample_encoded(s, WORLD_CACHE_LIGHT_EXPOSURE, WORLD_CACHE_LOG2_RADIANCE != 0);
      LightContribution c = light_contribution(r, p, n);
      float target = dot(c.wi, n) > 0.0 ? luminance(c.received_radiance) : 0.0;
      float weight = target * c.inverse_pdf / float(WORLD_CACHE_DI_SAMPLES);
      if (ris_update(ris, weight, target, rng_next_float(rng))) chosen = s;
    }
    if (chosen.valid != 0u) {
      ResolvedLightSample r = resolve_light_sample_encoded(chosen, WORLD_CACHE_LIGHT_EXPOSURE, WORLD_CACHE_LOG2_RADIANCE != 0);
      if (light_sample_visible(p, n, r))
        irradiance = light_contribution(r, p, n).received_radiance * ris_contribution_weight(ris);
    }
  }
  wc_new_radiance[i] = vec4(irradiance, 0.0);
}
