// The analytic distance field (the lesson's distance pass): the union of the
// shapes' SDFs at each pixel centre, kept as max(d, 0): 0 inside and on a
// shape, the distance to the nearest boundary outside.
#version 460
#include "gpu/shaders/rc_common.glsl"
#include "core/shared/rc/shapes.h"

layout(std430, set = 0, binding = BINDING_RC_SHAPES) readonly buffer Shapes { RcShape shapes[]; };
layout(std430, set = 0, binding = BINDING_RC_DISTANCE) writeonly buffer Distance { float distance_field[]; };

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  const vec2 centre = vec2(p) + 0.5f;
  float d = 1e6f;
  for (uint i = 0u; i < pc.shape_count; ++i) d = min(d, rc_sdf(centre, shapes[i]));
  distance_field[rc_texel(p)] = max(d, 0.0f);
}
