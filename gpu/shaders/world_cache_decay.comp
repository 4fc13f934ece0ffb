// World cache decay (docs/design.md §3 step 5; Solari's decay_world_cache): every
// cell loses one frame of life; a cell reaching 0 is cleared (checksum,
// radiance, luminance delta, root frame). Also starts the frame: no claims,
// no pending insertions, statistics zeroed; and counts each compaction
// block's live cells for the scan (world_cache_compact_scan), which would
// otherwise read the whole table again.
#version 460
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/world_cache_sweep.glsl"

layout(local_size_x = WORLD_CACHE_CELL_GROUP) in;

// An integer atomic sum: the same count in any order.
shared uint block_live;

void start_frame() {
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

// A live cell's new life; one reaching 0 is cleared.
uint decay_cell(uint cell, uint life) {
  life = world_cache_decayed_life(life);
  if (life == 0u) {
    wc_checksums[cell] = WORLD_CACHE_EMPTY_CELL;
    wc_radiance[cell] = vec4(0.0);
    wc_delta[cell] = 0.0;
    wc_root_frame[cell] = 0u;
  }
  return life;
}

void main() {
  if (gl_GlobalInvocationID.x == 0u) start_frame();
  if (gl_LocalInvocationID.x == 0u) block_live = 0u;
  barrier();
  const uint first = sweep_first_cell();
  uint live = 0u;
  for (uint q = 0u; q < SWEEP_QUADS; ++q) {
    const uint quad = first / 4u + q;
    wc_claims4[quad] = uvec4(WORLD_CACHE_NO_CLAIM);
    uvec4 life = wc_life4[quad];
    if (life == uvec4(0u)) continue;
    for (uint j = 0u; j < 4u; ++j)
      if (life[j] != 0u) life[j] = decay_cell(4u * quad + j, life[j]);
    wc_life4[quad] = life;
    live += live_count(life);
  }
  if (live != 0u) atomicAdd(block_live, live);
  barrier();
  if (gl_LocalInvocationID.x == 0u) wc_block_sums[gl_WorkGroupID.x] = block_live;
}
