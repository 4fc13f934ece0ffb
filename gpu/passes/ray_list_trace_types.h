// The ray-list pass (gpu/shaders/ray_list_trace.comp) that cross-checks the
// tracing backends and measures their ray rates: one ray in, one result out.
#ifndef GI_GPU_PASSES_RAY_LIST_TRACE_TYPES_H
#define GI_GPU_PASSES_RAY_LIST_TRACE_TYPES_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

GI_CONST uint BINDING_TEST_RAYS = 90u;     // TestRay[]
GI_CONST uint BINDING_TEST_RESULTS = 91u;  // TestResult[]
GI_CONST uint TEST_RAY_WORKGROUP = 64u;    // 64-128 traced fastest on lavapipe (docs/design.md §4)

// What the pass asks of each ray.
GI_CONST uint TRACE_MODE_CLOSEST = 1u;     // trace_closest
GI_CONST uint TRACE_MODE_UNOCCLUDED = 2u;  // trace_unoccluded

struct TestRay {
  vec4 origin_tmax;  // xyz origin, w tmax
  vec4 direction;    // xyz direction (any length), w unused
};

struct TestResult {
  float t;           // closest hit t (0 on a miss)
  uint instance;
  uint primitive;
  uint flags;        // bit 0: closest hit found, bit 1: unoccluded
  vec2 barycentrics;
  uint pad0;
  uint pad1;
};

GI_SHADER_END

#endif
