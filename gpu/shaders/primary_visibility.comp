// Primary visibility: one camera ray per pixel through the pixel centre (no
// AA jitter, DESIGN §3), closest hit written to the visibility buffer as
// (instance, primitive) — VISIBILITY_MISS on a miss — and its t to depth.
// Packed cluster/triangle ids replace the pair once clusters exist (DESIGN §8).
#version 460
#extension GL_GOOGLE_include_directive : require
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_VISIBILITY) writeonly buffer Visibility { uvec2 visibility[]; };
layout(std430, set = 0, binding = BINDING_DEPTH) writeonly buffer Depth { float depth[]; };

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;

  vec3 dir = camera_ray_direction(frame.camera, pixel, resolution);
  Hit hit;
  if (trace_closest(vec3(frame.camera.position), dir, RAY_TMAX, hit)) {
    visibility[index] = uvec2(hit.instance, hit.primitive);
    depth[index] = hit.t;
  } else {
    visibility[index] = uvec2(VISIBILITY_MISS);
    depth[index] = 0.0;
  }
}
