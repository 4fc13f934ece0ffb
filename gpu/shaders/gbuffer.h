// The G-buffer texel written by gbuffer_resolve.comp and its motion-vector
// projection, shared by C++ and GLSL (host_device.h rules). Whole vec4s only,
// so std430 and C++ agree (static_assert in gpu/passes/gbuffer_resolve.h).
#ifndef GI_GPU_SHADERS_GBUFFER_H
#define GI_GPU_SHADERS_GBUFFER_H
#include "core/shared/scene_types.h"

GI_SHADER_BEGIN

struct GBufferTexel {
  vec4 position_depth;         // xyz world position, w hit t along the camera ray (0 = miss)
  vec4 geometric_normal;       // xyz unit, w 1 on a hit, 0 on a miss
  vec4 shading_normal;         // xyz unit, w the material's brdf.model (gbuffer_brdf_model)
  vec4 base_color_metallic;    // rgb base colour, a metallic
  vec4 emissive_roughness;     // rgb emitted radiance (front face), a perceptual roughness
  vec4 motion_reflectance;     // xy motion in pixels (previous - current pixel), z 1 if valid, w reflectance
};

// Where world point p lands in a camera's image, in pixel coordinates (pixel
// centres at +0.5, so it inverts camera_ray_direction). False behind the camera.
GI_FN bool camera_project(GpuCamera c, vec3 p, uvec2 resolution, OUT(vec2) pixel) {
  vec3 d = p - vec3(c.position);
  vec3 f = vec3(c.forward);
  vec3 r = vec3(c.right);
  vec3 u = vec3(c.up);
  float s = dot(d, f) / dot(f, f);  // distance along forward, in units of |forward|
  pixel = vec2(0.0f);
  if (s <= 0.0f) return false;
  vec2 ndc = vec2(dot(d, r) / (s * dot(r, r)), -dot(d, u) / (s * dot(u, u)));
  pixel = (ndc + vec2(1.0f)) * 0.5f * vec2(resolution);
  return true;
}

// The last-frame pixel temporal reuse starts from: the motion vector's
// pixel, when the surface was in front of last frame's camera and on its
// screen. Otherwise there is none (own_pixel false, Solari 0.17 and 0.18:
// v0.18.0:realtime/restir_di.wgsl:161-163) or, with own_pixel (Solari 0.19:
// v0.19.0:realtime/restir_di.wgsl:147-149, restir_gi.wgsl:134-136), the pixel
// itself, which the surface test then accepts or refuses.
GI_FN bool temporal_source_pixel(uvec2 pixel, vec4 motion, uvec2 resolution, bool own_pixel, OUT(ivec2) q) {
  q = ivec2(floor(vec2(pixel) + vec2(0.5f) + vec2(motion.x, motion.y)));
  bool on_screen = motion.z > 0.0f && all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, ivec2(resolution)));
  if (!on_screen && own_pixel) {
    q = ivec2(pixel);
    return true;
  }
  return on_screen;
}

// The material model (brdf.h's BRDF_*) the texel's surface is shaded with.
GI_FN uint gbuffer_brdf_model(GBufferTexel g) { return uint(g.shading_normal.w); }

GI_SHADER_END

#endif
