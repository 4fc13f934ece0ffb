// World cache compaction, level 1 of 2 (docs/design.md §3 step 5): live cells
// (life != 0) per block of WORLD_CACHE_SCAN_BLOCK cells.
#version 460
#include "gpu/shaders/world_cache_common.glsl"

// A quarter of the scan's threads, 16 cells each: the same count with fewer
// invocations for lavapipe to start.
const uint COUNT_THREADS = WORLD_CACHE_SCAN_THREADS / 4u;
const uint COUNT_CELLS = WORLD_CACHE_SCAN_BLOCK / COUNT_THREADS;
layout(local_size_x = COUNT_THREADS) in;

// An integer atomic sum: the same count in any order, with two barriers
// instead of a tree's eight (barriers are what a block costs on lavapipe).
shared uint block_count;

void main() {
  uint t = gl_LocalInvocationID.x;
  if (t == 0u) block_count = 0u;
  barrier();
  uint base = gl_WorkGroupID.x * WORLD_CACHE_SCAN_BLOCK + t;
  uint n = 0u;
  for (uint k = 0u; k < COUNT_CELLS; ++k) n += wc_life[base + k * COUNT_THREADS] != 0u ? 1u : 0u;
  if (n != 0u) atomicAdd(block_count, n);
  barrier();
  if (t == 0u) wc_block_sums[gl_WorkGroupID.x] = block_count;
}
