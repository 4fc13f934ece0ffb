// End-of-frame statistics for the checks (docs/design.md §6; integer atomics, so the
// figures are the same at any thread count): live and sampled cells, the
// fixed-point radiance sum, the cells this frame's update blended, and — with root-frame instrumentation — cells
// older than lifetime + 1 frames since their last pixel-rooted refresh.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "core/shared/scene_types.h"
#include "gpu/shaders/bindings.h"
#include "gpu/shaders/world_cache_common.glsl"

layout(std140, set = 0, binding = BINDING_FRAME) uniform Frame { FrameConstants frame; };

layout(local_size_x = WORLD_CACHE_CELL_GROUP) in;

void cell_stats(uint cell) {
  // The same invocation also reads active-list entry `cell`: w = 1 marks one
  // the soft cap left out (world_cache_sample_di).
  if (cell < wc_counters.active_args.w && wc_new_radiance[cell].w == 0.0) atomicAdd(wc_stats.updated_cells, 1u);
  uint life = wc_life[cell];
  if (life == 0u) {
    if (wc_checksums[cell] != WORLD_CACHE_EMPTY_CELL) atomicAdd(wc_stats.dead_not_empty, 1u);
    return;
  }
  atomicAdd(wc_stats.live_cells, 1u);
  if (life > uint(WORLD_CACHE_LIFETIME)) atomicAdd(wc_stats.life_out_of_range, 1u);
  vec4 r = wc_radiance[cell];
  if (any(isnan(r)) || any(isinf(r))) {
    atomicAdd(wc_stats.nonfinite_cells, 1u);
  } else if (r.w > 0.0) {
    atomicAdd(wc_stats.sampled_cells, 1u);
    uint v = uint(min(luminance(r.rgb) * WORLD_CACHE_STATS_SCALE, 2147483647.0));
    uint old = atomicAdd(wc_stats.radiance_sum_lo, v);
    if (old + v < old) atomicAdd(wc_stats.radiance_sum_hi, 1u);
  }
#ifdef WORLD_CACHE_ROOT_FRAME
  uint age = world_cache_age(frame.resolution_frame.z, wc_root_frame[cell]);
  atomicMax(wc_stats.oldest_age, age);
  if (!world_cache_age_ok(frame.resolution_frame.z, wc_root_frame[cell], uint(WORLD_CACHE_LIFETIME)))
    atomicAdd(wc_stats.over_age_cells, 1u);
#endif
}

void main() {
  const uint first = gl_WorkGroupID.x * WORLD_CACHE_CELL_GROUP * WORLD_CACHE_SWEEP_CELLS + gl_LocalInvocationID.x;
  for (uint k = 0u; k < WORLD_CACHE_SWEEP_CELLS; ++k) {
    const uint cell = first + k * WORLD_CACHE_CELL_GROUP;
    if (cell < uint(WORLD_CACHE_CELLS)) cell_stats(cell);
  }
}
