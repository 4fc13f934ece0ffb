// Traces a list of rays through the tracing interface every pass uses
// (trace_closest / trace_unoccluded from scene_bindings.glsl) and writes one
// result per ray: the backend cross-check test and the ray-rate benchmark
// compile it once per backend and compare.
#version 460
#extension GL_GOOGLE_include_directive : require
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/passes/ray_list_trace_types.h"

layout(local_size_x = TEST_RAY_WORKGROUP) in;

layout(std430, set = 0, binding = BINDING_TEST_RAYS) readonly buffer Rays { TestRay rays[]; };
layout(std430, set = 0, binding = BINDING_TEST_RESULTS) writeonly buffer Results { TestResult results[]; };
layout(push_constant) uniform Push {
  uint ray_count;
  uint mode;  // TRACE_MODE_* bits
} push;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.ray_count) return;
  TestRay ray = rays[i];
  vec3 origin = ray.origin_tmax.xyz;
  vec3 dir = ray.direction.xyz;
  TestResult r;
  r.t = 0.0;
  r.instance = 0u;
  r.primitive = 0u;
  r.flags = 0u;
  r.barycentrics = vec2(0.0);
  r.pad0 = 0u;
  r.pad1 = 0u;
  if ((push.mode & TRACE_MODE_CLOSEST) != 0u) {
    Hit hit;
    if (trace_closest(origin, dir, ray.origin_tmax.w, hit)) {
      r.t = hit.t;
      r.instance = hit.instance;
      r.primitive = hit.primitive;
      r.barycentrics = hit.barycentrics;
      r.flags |= 1u;
    }
  }
  if ((push.mode & TRACE_MODE_UNOCCLUDED) != 0u && trace_unoccluded(origin, dir, ray.origin_tmax.w)) r.flags |= 2u;
  results[i] = r;
}
