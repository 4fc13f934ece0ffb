// Turns a query pass's pending-insertion count into the indirect dispatch of
// its commit (wc_push.pass_kind: 0 cache-to-cache, 1 pixel-rooted).
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(push_constant) uniform WcPushBlock { WorldCachePush wc_push; };

layout(local_size_x = 1) in;

void main() {
  uint n = min(wc_push.pass_kind == 0u ? wc_counters.gi_pending.w : wc_counters.pixel_pending.w,
               uint(WORLD_CACHE_PENDING_CAPACITY));
  uvec4 args = uvec4((n + WORLD_CACHE_CELL_GROUP - 1u) / WORLD_CACHE_CELL_GROUP, 1u, 1u, n);
  if (wc_push.pass_kind == 0u) wc_counters.gi_pending = args;
  else wc_counters.pixel_pending = args;
}
