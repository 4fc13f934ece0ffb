// Commits the insertions a query pass asked for (docs/design.md §3 step 5, made
// deterministic): per slot, the record of the lowest query id — the one still
// holding the claim — writes checksum, life, root frame and geometry. Losers
// try again next frame, when they find the slot taken and probe on.
#version 460
#include "gpu/shaders/world_cache_common.glsl"

layout(push_constant) uniform WcPushBlock { WorldCachePush wc_push; };

layout(local_size_x = WORLD_CACHE_CELL_GROUP) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint n = wc_push.pass_kind == 0u ? wc_counters.gi_pending.w : wc_counters.pixel_pending.w;
  if (i >= n) return;
  WorldCachePending p = wc_pending[i];
  if (wc_claims[p.slot] != p.query_id) return;
  wc_checksums[p.slot] = p.checksum;
  wc_life[p.slot] = p.life;
#ifdef WORLD_CACHE_ROOT_FRAME
  wc_root_frame[p.slot] = p.root_frame;
#endif
  WorldCacheGeometry g;
  g.position = vec4(p.position_x, p.position_y, p.position_z, 0.0);
  g.normal = vec4(unpack_unit_vector(p.normal), 0.0);
  wc_geometry[p.slot] = g;
  wc_radiance[p.slot] = vec4(0.0);
  wc_delta[p.slot] = 0.0;
}
