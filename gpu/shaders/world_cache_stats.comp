// End-of-frame statistics for the checks (docs/design.md §6; integer atomics, so the
// figures are the same at any thread count): live and sampled cells, the
// fixed-point radiance sum, the cells this frame's update blended, and — with root-frame instrumentation — cells
// older than lifetime + 1 frames since their last pixel-rooted refresh.
// Each invocation sums its run of cells and adds its sums once.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "core/shared/scene_types.h"
#include "gpu/shaders/bindings.h"
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/world_cache_sweep.glsl"

layout(std140, set = 0, binding = BINDING_FRAME) uniform Frame { FrameConstants frame; };

layout(local_size_x = WORLD_CACHE_CELL_GROUP) in;

struct RunStats {
  uint live, sampled, sum_lo, sum_hi, over_age, oldest_age, life_out_of_range, dead_not_empty, nonfinite;
};

// A 64-bit sum in two words: exact, so the same total in any order.
void add_radiance(inout RunStats s, uint v) {
  const uint lo = s.sum_lo + v;
  if (lo < v) ++s.sum_hi;
  s.sum_lo = lo;
}

void live_cell_stats(inout RunStats s, uint cell, uint life) {
  ++s.live;
  if (life > uint(WORLD_CACHE_LIFETIME)) ++s.life_out_of_range;
  const vec4 r = wc_radiance[cell];
  if (any(isnan(r)) || any(isinf(r))) {
    ++s.nonfinite;
  } else if (r.w > 0.0) {
    ++s.sampled;
    add_radiance(s, uint(min(luminance(r.rgb) * WORLD_CACHE_STATS_SCALE, 2147483647.0)));
  }
#ifdef WORLD_CACHE_ROOT_FRAME
  s.oldest_age = max(s.oldest_age, world_cache_age(frame.resolution_frame.z, wc_root_frame[cell]));
  if (!world_cache_age_ok(frame.resolution_frame.z, wc_root_frame[cell], uint(WORLD_CACHE_LIFETIME))) ++s.over_age;
#endif
}

void add_to_frame(RunStats s, uint updated) {
  if (updated != 0u) atomicAdd(wc_stats.updated_cells, updated);
  if (s.dead_not_empty != 0u) atomicAdd(wc_stats.dead_not_empty, s.dead_not_empty);
  if (s.live == 0u) return;
  atomicAdd(wc_stats.live_cells, s.live);
  if (s.life_out_of_range != 0u) atomicAdd(wc_stats.life_out_of_range, s.life_out_of_range);
  if (s.nonfinite != 0u) atomicAdd(wc_stats.nonfinite_cells, s.nonfinite);
  if (s.sampled != 0u) atomicAdd(wc_stats.sampled_cells, s.sampled);
  if (s.sum_lo != 0u) {
    const uint old = atomicAdd(wc_stats.radiance_sum_lo, s.sum_lo);
    if (old + s.sum_lo < old) ++s.sum_hi;
  }
  if (s.sum_hi != 0u) atomicAdd(wc_stats.radiance_sum_hi, s.sum_hi);
#ifdef WORLD_CACHE_ROOT_FRAME
  atomicMax(wc_stats.oldest_age, s.oldest_age);
  if (s.over_age != 0u) atomicAdd(wc_stats.over_age_cells, s.over_age);
#endif
}

void main() {
  const uint first = sweep_first_cell();
  RunStats s = RunStats(0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
  for (uint q = 0u; q < SWEEP_QUADS; ++q) {
    const uint quad = first / 4u + q;
    const uvec4 life = wc_life4[quad];
    const uvec4 checksum = wc_checksums4[quad];
    if (life == uvec4(0u)) {  // most of the table
      const uvec4 kept = uvec4(notEqual(checksum, uvec4(WORLD_CACHE_EMPTY_CELL)));
      s.dead_not_empty += kept.x + kept.y + kept.z + kept.w;
      continue;
    }
    for (uint j = 0u; j < 4u; ++j) {
      if (life[j] != 0u) live_cell_stats(s, 4u * quad + j, life[j]);
      else if (checksum[j] != WORLD_CACHE_EMPTY_CELL) ++s.dead_not_empty;
    }
  }
  // The same run of indices into the active list: w = 1 marks an entry the
  // soft cap left out (world_cache_sample_di).
  const uint active_entries = wc_counters.active_args.w;
  uint updated = 0u;
  for (uint k = 0u; k < WORLD_CACHE_SWEEP_CELLS && first + k < active_entries; ++k)
    updated += uint(wc_new_radiance[first + k].w == 0.0);
  add_to_frame(s, updated);
}
