// The output (the lesson's rc_apply): the scene plus the mipmap's radiance,
// sampled bilinearly at the pixel centre with clamp-to-edge addressing (the
// lesson's linear sampler); mipmap texel q stands at the centre of probe q.
#version 460
#include "gpu/shaders/rc_common.glsl"

layout(std430, set = 0, binding = BINDING_RC_SCENE) readonly buffer Scene { vec4 scene[]; };
layout(std430, set = 0, binding = BINDING_RC_MIPMAP) readonly buffer Mipmap { vec4 mipmap[]; };
layout(std430, set = 0, binding = BINDING_RC_OUTPUT) writeonly buffer Output { vec4 result[]; };

vec4 mip(ivec2 q) {
  q = clamp(q, ivec2(0), ivec2(pc.mip_width, pc.mip_height) - 1);
  return mipmap[uint(q.y) * pc.mip_width + uint(q.x)];
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  const vec2 at = (vec2(p) + 0.5f) / float(pc.probe_width) - 0.5f;
  const vec2 base = floor(at);
  const vec2 f = at - base;
  const ivec2 b = ivec2(base);
  const vec4 radiance = mix(mix(mip(b), mip(b + ivec2(1, 0)), f.x), mix(mip(b + ivec2(0, 1)), mip(b + ivec2(1, 1)), f.x), f.y);
  result[rc_texel(p)] = vec4(scene[rc_texel(p)].rgb + radiance.rgb, 1.0f);
}
