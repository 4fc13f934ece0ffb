// One jump-flooding round: each pixel looks at its own seed and those of the
// eight pixels pc.jfa_step away and keeps the nearest (ties: the first in
// this fixed order, so the result does not depend on scheduling). The last
// round (step 1) also writes the distance field: the distance between pixel
// centres less half a pixel, the boundary lying between the two centres,
// so that it means what the analytic field means.
#version 460
#include "gpu/shaders/rc_common.glsl"

layout(std430, set = 0, binding = BINDING_RC_SEEDS_IN) readonly buffer SeedsIn { uint seeds_in[]; };
layout(std430, set = 0, binding = BINDING_RC_SEEDS_OUT) writeonly buffer SeedsOut { uint seeds_out[]; };
layout(std430, set = 0, binding = BINDING_RC_DISTANCE) writeonly buffer Distance { float distance_field[]; };

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  uint best = RC_NO_SEED;
  uint best_d2 = 0xffffffffu;
  const int k = int(pc.jfa_step);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const ivec2 q = ivec2(p) + ivec2(dx, dy) * k;
      if (q.x < 0 || q.y < 0 || q.x >= int(pc.width) || q.y >= int(pc.height)) continue;
      const uint seed = seeds_in[rc_texel(uvec2(q))];
      if (seed == RC_NO_SEED) continue;
      const ivec2 s = ivec2(int(seed & 0xffffu), int(seed >> 16u));
      const ivec2 d = s - ivec2(p);
      const uint d2 = uint(d.x * d.x + d.y * d.y);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = seed;
      }
    }
  seeds_out[rc_texel(p)] = best;
  if (pc.jfa_last != 0u)
    distance_field[rc_texel(p)] = best == RC_NO_SEED ? 1e6f : max(sqrt(float(best_d2)) - 0.5f, 0.0f);
}
