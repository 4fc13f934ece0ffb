// World cache compaction, level 1 of 2 (DESIGN §3 step 5): live cells
// (life != 0) per block of WORLD_CACHE_SCAN_BLOCK cells.
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(local_size_x = WORLD_CACHE_SCAN_THREADS) in;

// An integer atomic sum: the same count in any order, with two barriers
// instead of a tree's eight (barriers are what a block costs on lavapipe).
shared uint block_count;

void main() {
  uint t = gl_LocalInvocationID.x;
  if (t == 0u) block_count = 0u;
  barrier();
  uint base = gl_WorkGroupID.x * WORLD_CACHE_SCAN_BLOCK + t * 4u;
  uint n = 0u;
  for (uint k = 0u; k < 4u; ++k) n += wc_life[base + k] != 0u ? 1u : 0u;
  if (n != 0u) atomicAdd(block_count, n);
  barrier();
  if (t == 0u) wc_block_sums[gl_WorkGroupID.x] = block_count;
}
