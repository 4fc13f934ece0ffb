// One cascade of probes (the lesson's rc_cascade_first and rc_cascade_merge,
// by pc.merge). Each texel is one ray of one probe: the probe is the
// width × width block it lies in, the ray its index in the block. The ray
// marches the distance field from the probe centre + start along its
// direction until it has covered `range`, hits (distance below the
// epsilon: it returns the scene texel there, alpha 1), leaves the canvas or
// runs out of steps. A ray that does not hit takes, when merging, the
// coarser cascade's radiance in its direction: the four nearest coarser
// probes, bilinearly, each the mean of its four rays that subdivide this one.
// With RC_MERGE_BILINEAR_FIX (profile key rc.merge) the fine ray's own march
// is replaced, for each coarser probe, by a march from the fine interval's
// start to where that probe's interval starts, so light reaches this probe
// only along a path that exists from here: across a thin wall the lesson's
// merge takes the far side's probes as they are.
#version 460
#include "gpu/shaders/rc_common.glsl"

layout(std430, set = 0, binding = BINDING_RC_SCENE) readonly buffer Scene { vec4 scene[]; };
layout(std430, set = 0, binding = BINDING_RC_DISTANCE) readonly buffer Distance { float distance_field[]; };
layout(std430, set = 0, binding = BINDING_RC_CASCADE_SOURCE) readonly buffer Source { vec4 source[]; };
layout(std430, set = 0, binding = BINDING_RC_CASCADE_DEST) writeonly buffer Dest { vec4 dest[]; };

vec4 raymarch(vec2 origin, vec2 dir, float range) {
  const vec2 size = vec2(pc.width, pc.height);
  vec2 position = origin;
  float covered = 0.0f;
  for (uint step = 0u; step < pc.max_steps; ++step) {
    if (covered >= range || any(greaterThanEqual(position, size)) || any(lessThan(position, vec2(0.0f)))) break;
    // The lesson's code reads the texel whose index is nearest the position.
    const uvec2 texel = uvec2(clamp(ivec2(round(position)), ivec2(0), ivec2(pc.width, pc.height) - 1));
    const float dist = distance_field[rc_texel(texel)];
    if (dist < pc.hit_epsilon) return vec4(scene[rc_texel(texel)].rgb, 1.0f);
    position += dir * dist;
    covered += dist;
  }
  return vec4(0.0f);
}

vec4 fetch_coarser(ivec2 cell, ivec2 corner, uvec2 ray_texel, uint coarse_width) {
  const ivec2 last = ivec2(pc.width / coarse_width, pc.height / coarse_width) - 1;
  const ivec2 q = clamp(rc_upper_probe(cell, corner), ivec2(0), max(last, ivec2(0)));
  return source[rc_texel(uvec2(q) * coarse_width + ray_texel)];
}

vec4 merge(ivec2 cell, uint ray_index) {
  const uint coarse_width = pc.probe_width * 2u;
  vec4 tl = vec4(0.0f), tr = vec4(0.0f), bl = vec4(0.0f), br = vec4(0.0f);
  for (uint k = 0u; k < 4u; ++k) {
    const uint coarse_ray = ray_index * 4u + k;
    const uvec2 ray_texel = uvec2(coarse_ray % coarse_width, coarse_ray / coarse_width);
    tl += fetch_coarser(cell, ivec2(-1, -1), ray_texel, coarse_width);
    tr += fetch_coarser(cell, ivec2(0, -1), ray_texel, coarse_width);
    bl += fetch_coarser(cell, ivec2(-1, 0), ray_texel, coarse_width);
    br += fetch_coarser(cell, ivec2(0, 0), ray_texel, coarse_width);
  }
  const vec2 w = rc_merge_weight(cell);
  return mix(mix(tl, tr, w.x), mix(bl, br, w.x), w.y) * 0.25f;
}

vec4 merge_fixed(ivec2 cell, uint ray_index, vec2 centre) {
  const uint coarse_width = pc.probe_width * 2u;
  const uint coarse_rays = coarse_width * coarse_width;
  const float coarse_start = pc.probe_start + pc.probe_range;
  const ivec2 last = max(ivec2(pc.width / coarse_width, pc.height / coarse_width) - 1, ivec2(0));
  vec4 corners[4] = vec4[4](vec4(0.0f), vec4(0.0f), vec4(0.0f), vec4(0.0f));
  for (uint k = 0u; k < 4u; ++k) {
    const uint coarse_ray = ray_index * 4u + k;
    const vec2 dir = rc_ray_direction(coarse_ray, coarse_rays);
    const uvec2 ray_texel = uvec2(coarse_ray % coarse_width, coarse_ray / coarse_width);
    const vec2 from = centre + dir * pc.probe_start;
    for (uint j = 0u; j < 4u; ++j) {
      const ivec2 q = clamp(rc_upper_probe(cell, ivec2(int(j & 1u), int(j >> 1u)) - 1), ivec2(0), last);
      const vec2 to = vec2(uvec2(q) * coarse_width + coarse_width / 2u) + dir * coarse_start;
      const float len = length(to - from);
      const vec4 hit = len > 0.0f ? raymarch(from, (to - from) / len, len) : vec4(0.0f);
      corners[j] += hit.a == 1.0f ? hit : hit + source[rc_texel(uvec2(q) * coarse_width + ray_texel)];
    }
  }
  const vec2 w = rc_merge_weight(cell);
  return mix(mix(corners[0], corners[1], w.x), mix(corners[2], corners[3], w.x), w.y) * 0.25f;
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.width || p.y >= pc.height) return;
  const uint w = pc.probe_width;
  const uvec2 in_probe = p % w;
  const uint ray_index = in_probe.x + in_probe.y * w;
  const vec2 dir = rc_ray_direction(ray_index, w * w);
  const uvec2 cell = p / w;
  const vec2 centre = vec2(cell * w + w / 2u);
  vec4 color;
  if (pc.merge != 0u && pc.merge_fix == RC_MERGE_BILINEAR_FIX) {
    color = merge_fixed(ivec2(cell), ray_index, centre);
  } else {
    color = raymarch(centre + dir * pc.probe_start, dir, pc.probe_range);
    if (pc.merge != 0u && color.a != 1.0f) color += merge(ivec2(cell), ray_index);
  }
  dest[rc_texel(p)] = color;
}
