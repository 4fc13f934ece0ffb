// World cache compaction, level 2 (docs/design.md §3 step 5): one workgroup turns the
// block counts into exclusive offsets, writes the active count and the
// indirect dispatch of the per-active-cell passes.
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(local_size_x = WORLD_CACHE_SCAN_THREADS) in;

shared uint partial[WORLD_CACHE_SCAN_THREADS];

void main() {
  uint t = gl_LocalInvocationID.x;
  uint blocks = uint(WORLD_CACHE_CELLS) / WORLD_CACHE_SCAN_BLOCK;
  uint per_thread = (blocks + WORLD_CACHE_SCAN_THREADS - 1u) / WORLD_CACHE_SCAN_THREADS;
  uint first = t * per_thread;
  uint last = min(first + per_thread, blocks);
  uint sum = 0u;
  for (uint b = first; b < last; ++b) sum += wc_block_sums[b];
  partial[t] = sum;
  barrier();
  // Inclusive Hillis-Steele scan over the threads' sums.
  for (uint stride = 1u; stride < WORLD_CACHE_SCAN_THREADS; stride *= 2u) {
    uint v = t >= stride ? partial[t - stride] : 0u;
    barrier();
    partial[t] += v;
    barrier();
  }
  uint offset = partial[t] - sum;
  for (uint b = first; b < last; ++b) {
    uint c = wc_block_sums[b];
    wc_block_sums[b] = offset;
    offset += c;
  }
  if (t == WORLD_CACHE_SCAN_THREADS - 1u) {
    uint total = partial[t];
    wc_counters.active_args =
        uvec4((total + uint(WORLD_CACHE_UPDATE_GROUP) - 1u) / uint(WORLD_CACHE_UPDATE_GROUP), 1u, 1u, total);
  }
}
