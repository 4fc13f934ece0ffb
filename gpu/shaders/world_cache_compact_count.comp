// World cache compaction, level 1 of 2 (DESIGN §3 step 5): live cells
// (life != 0) per block of WORLD_CACHE_SCAN_BLOCK cells.
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(local_size_x = WORLD_CACHE_SCAN_THREADS) in;

shared uint partial[WORLD_CACHE_SCAN_THREADS];

void main() {
  uint t = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * WORLD_CACHE_SCAN_BLOCK + t * 4u;
  uint n = 0u;
  for (uint k = 0u; k < 4u; ++k) n += wc_life[base + k] != 0u ? 1u : 0u;
  partial[t] = n;
  barrier();
  for (uint stride = WORLD_CACHE_SCAN_THREADS / 2u; stride > 0u; stride /= 2u) {
    if (t < stride) partial[t] += partial[t + stride];
    barrier();
  }
  if (t == 0u) wc_block_sums[gl_WorkGroupID.x] = partial[0];
}
