// The lesson's tex_main: what a ray that hits sees. Each pixel takes the
// radiance of the last listed shape that covers its centre (painter's
// order), alpha 1; uncovered pixels are (0, 0, 0, 0).
#version 460
#include "gpu/shaders/rc_common.glsl"
#include "core/shared/rc/shapes.h"

layout(std430, set = 0, binding = BINDING_RC_SHAPES) readonly buffer Shapes { RcShape shapes[]; };
layout(std430, set = 0, binding = BINDING_RC_SCENE) writeonly buffer Scene { vec4 scene[]; };

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  const vec2 centre = vec2(p) + 0.5f;
  vec4 texel = vec4(0.0f);
  for (uint i = 0u; i < pc.shape_count; ++i)
    if (rc_sdf(centre, shapes[i]) <= 0.0f) texel = vec4(shapes[i].radiance.rgb, 1.0f);
  scene[rc_texel(p)] = texel;
}
