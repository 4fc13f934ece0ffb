// World cache decay (docs/design.md §3 step 5; Solari's decay_world_cache): every
// cell loses one frame of life; a cell reaching 0 is cleared (checksum,
// radiance, luminance delta, root frame). Also starts the frame: no claims,
// no pending insertions, statistics zeroed.
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(local_size_x = WORLD_CACHE_CELL_GROUP) in;

void decay_cell(uint cell) {
  wc_claims[cell] = WORLD_CACHE_NO_CLAIM;
  uint life = wc_life[cell];
  if (life == 0u) return;
  life = world_cache_decayed_life(life);
  wc_life[cell] = life;
  if (life == 0u) {
    wc_checksums[cell] = WORLD_CACHE_EMPTY_CELL;
    wc_radiance[cell] = vec4(0.0);
    wc_delta[cell] = 0.0;
    wc_root_frame[cell] = 0u;
  }
}

void main() {
  if (gl_GlobalInvocationID.x == 0u) {
    wc_counters.gi_pending = uvec4(0u, 1u, 1u, 0u);
    wc_counters.pixel_pending = uvec4(0u, 1u, 1u, 0u);
    WorldCacheStats s;
    s.live_cells = 0u;
    s.sampled_cells = 0u;
    s.radiance_sum_lo = 0u;
    s.radiance_sum_hi = 0u;
    s.over_age_cells = 0u;
    s.oldest_age = 0u;
    s.life_out_of_range = 0u;
    s.dead_not_empty = 0u;
    s.nonfinite_cells = 0u;
    s.updated_cells = 0u;
    s.pad1 = 0u;
    s.pad2 = 0u;
    wc_stats = s;
  }
  const uint first = gl_WorkGroupID.x * WORLD_CACHE_CELL_GROUP * WORLD_CACHE_SWEEP_CELLS + gl_LocalInvocationID.x;
  for (uint k = 0u; k < WORLD_CACHE_SWEEP_CELLS; ++k) {
    const uint cell = first + k * WORLD_CACHE_CELL_GROUP;
    if (cell < uint(WORLD_CACHE_CELLS)) decay_cell(cell);
  }
}
