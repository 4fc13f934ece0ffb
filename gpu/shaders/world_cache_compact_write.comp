// World cache compaction, final step (docs/design.md §3 step 5): every live cell's
// index at its block offset plus its rank within the block, so the active
// list is in ascending cell order (deterministic).
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(local_size_x = WORLD_CACHE_SCAN_THREADS) in;

shared uint partial[WORLD_CACHE_SCAN_THREADS];

void main() {
  // The block's live count from the exclusive offsets the scan left: an
  // empty block (most of the table in a small scene) writes nothing and
  // skips the scan below (uniform over the group, so no barrier is skipped
  // by half of it).
  uint block = gl_WorkGroupID.x;
  uint blocks = uint(WORLD_CACHE_CELLS) / WORLD_CACHE_SCAN_BLOCK;
  uint block_end = block + 1u < blocks ? wc_block_sums[block + 1u] : wc_counters.active_args.w;
  if (block_end == wc_block_sums[block]) return;
  uint t = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * WORLD_CACHE_SCAN_BLOCK + t * 4u;
  uint n = 0u;
  for (uint k = 0u; k < 4u; ++k) n += wc_life[base + k] != 0u ? 1u : 0u;
  partial[t] = n;
  barrier();
  for (uint stride = 1u; stride < WORLD_CACHE_SCAN_THREADS; stride *= 2u) {
    uint v = t >= stride ? partial[t - stride] : 0u;
    barrier();
    partial[t] += v;
    barrier();
  }
  uint out_index = wc_block_sums[gl_WorkGroupID.x] + partial[t] - n;
  for (uint k = 0u; k < 4u; ++k) {
    if (wc_life[base + k] != 0u) {
      wc_active[out_index] = base + k;
      ++out_index;
    }
  }
}
