// Jump flooding, round 0: every pixel inside a shape (the scene's alpha) is
// its own nearest seed; the others have none yet.
#version 460
#include "gpu/shaders/rc_common.glsl"

layout(std430, set = 0, binding = BINDING_RC_SCENE) readonly buffer Scene { vec4 scene[]; };
layout(std430, set = 0, binding = BINDING_RC_SEEDS_OUT) writeonly buffer Seeds { uint seeds[]; };

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  seeds[rc_texel(p)] = scene[rc_texel(p)].a == 1.0f ? (p.x | (p.y << 16u)) : RC_NO_SEED;
}
