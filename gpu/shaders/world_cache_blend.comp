// World cache blend (docs/design.md §3 step 5; Solari's blend_new_samples): per
// active cell, this frame's sample into the running irradiance: the fixed
// blend of 0.17 or the adaptive blend of 0.18 (core/shared/world_cache.h). A
// separate dispatch from the sampling, which reads last frame's radiance.
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(local_size_x = WORLD_CACHE_UPDATE_GROUP) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= wc_counters.active_args.w) return;
  if (wc_new_radiance[i].w != 0.0) return;  // left out by the soft cap (world_cache_sample_di)
  uint cell = wc_active[i];
  vec3 new_radiance = wc_new_radiance[i].rgb;
#if WORLD_CACHE_ADAPTIVE
  WorldCacheBlend b = world_cache_blend_adaptive(wc_radiance[cell], wc_delta[cell], new_radiance,
                                                 float(WORLD_CACHE_MAX_SAMPLES), float(WORLD_CACHE_ADAPTIVE_EXPONENT),
                                                 float(WORLD_CACHE_DELTA_BLEND));
#else
  WorldCacheBlend b = world_cache_blend_fixed(wc_radiance[cell], new_radiance, float(WORLD_CACHE_MAX_SAMPLES));
#endif
  wc_radiance[cell] = b.radiance;
  wc_delta[cell] = b.luminance_delta;
}
