// One texel per cascade-0 probe: the sum of its width × width rays divided
// by RC_MIPMAP_PROBE_WIDTH_X2's width·2 (the lesson's) or by the ray count
// width² (profile key rc.mipmap_divisor). Texels past the canvas edge (a
// probe cut by it) are left out of the sum, not the divisor.
#version 460
#include "gpu/shaders/rc_common.glsl"

layout(std430, set = 0, binding = BINDING_RC_CASCADE_SOURCE) readonly buffer Cascade0 { vec4 cascade0[]; };
layout(std430, set = 0, binding = BINDING_RC_MIPMAP) writeonly buffer Mipmap { vec4 mipmap[]; };

void main() {
  const uvec2 q = gl_GlobalInvocationID.xy;
  if (q.x >= pc.mip_width || q.y >= pc.mip_height) return;
  const uint w = pc.probe_width;
  vec4 sum = vec4(0.0f);
  for (uint y = 0u; y < w; ++y)
    for (uint x = 0u; x < w; ++x) {
      const uvec2 p = q * w + uvec2(x, y);
      if (p.x < pc.width && p.y < pc.height) sum += cascade0[rc_texel(p)];
    }
  mipmap[q.y * pc.mip_width + q.x] = sum / rc_mipmap_divisor(w, pc.mipmap_mode);
}
