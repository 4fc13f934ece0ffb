// World cache compaction, final step (docs/design.md §3 step 5): every live cell's
// index at its block offset plus its rank within the block, so the active
// list is in ascending cell order (deterministic).
#version 460
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/world_cache_sweep.glsl"

layout(local_size_x = WORLD_CACHE_CELL_GROUP) in;

// Each invocation's live count, four invocations to a uvec4: an invocation's
// rank in its block is the sum of the counts before it, read after one
// barrier (a tree scan's sixteen barriers are what a block cost on lavapipe).
shared uvec4 run_counts[WORLD_CACHE_CELL_GROUP / 4u];

void main() {
  // The block's live count from the exclusive offsets the scan left: an
  // empty block (most of the table in a small scene) writes nothing and
  // skips the barrier below (uniform over the group, so no barrier is
  // skipped by half of it).
  const uint block = gl_WorkGroupID.x;
  const uint blocks = uint(WORLD_CACHE_CELLS) / WORLD_CACHE_SCAN_BLOCK;
  const uint block_end = block + 1u < blocks ? wc_block_sums[block + 1u] : wc_counters.active_args.w;
  if (block_end == wc_block_sums[block]) return;
  const uint t = gl_LocalInvocationID.x;
  const uint first = sweep_first_cell();
  uvec4 life[SWEEP_QUADS];
  uint n = 0u;
  for (uint q = 0u; q < SWEEP_QUADS; ++q) {
    life[q] = wc_life4[first / 4u + q];
    n += live_count(life[q]);
  }
  run_counts[t / 4u][t % 4u] = n;
  barrier();
  uvec4 before = uvec4(0u);
  for (uint i = 0u; i < t / 4u; ++i) before += run_counts[i];
  uint out_index = wc_block_sums[block] + before.x + before.y + before.z + before.w;
  for (uint j = 0u; j < t % 4u; ++j) out_index += run_counts[t / 4u][j];
  for (uint q = 0u; q < SWEEP_QUADS; ++q)
    for (uint j = 0u; j < 4u; ++j)
      if (life[q][j] != 0u) wc_active[out_index++] = first + 4u * q + j;
}
