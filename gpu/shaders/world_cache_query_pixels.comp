// The cache view: a pixel-rooted query at each pixel's primary surface (the
// query ReSTIR GI and specular GI will make), irradiance written per pixel
// (w 1 on a surface). Full lifetime; root frame = this frame.
#version 460
#extension GL_GOOGLE_include_directive : require
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/shaders/gbuffer.h"
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/world_cache_query.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_GBUFFER) readonly buffer GBuffer { GBufferTexel gbuffer[]; };

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  GBufferTexel g = gbuffer[index];
  if (g.geometric_normal.w <= 0.0) {
    wc_view[index] = vec4(0.0);
    return;
  }
  vec3 dir = camera_ray_direction(frame.camera, pixel, resolution);
  vec3 n = dot(dir, g.geometric_normal.xyz) < 0.0 ? g.geometric_normal.xyz : -g.geometric_normal.xyz;
  uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_WORLD_CACHE_VIEW, index, frame.resolution_frame.z);
  vec3 e = world_cache_query(g.position_depth.xyz, n, 1e30, false, uint(WORLD_CACHE_LIFETIME),
                             frame.resolution_frame.z, index, 1u, rng);
  wc_view[index] = vec4(e, 1.0);
}
