// GPU reference mode: the unbiased path tracer of core/shared/path_integrator.h
// (the same code as the Embree reference), counts.z samples per pixel per
// frame, accumulated as sums into two halves by sample-index parity so that
// the two half means estimate the noise. A non-finite sample is counted in
// the nonfinite buffer and contributes nothing (never dropped silently).
//
// Defines: REFERENCE_MAX_BOUNCES (path length cap, shared with the Embree
// reference); REFERENCE_BACKGROUND (vec3, Scene::background), if not black;
// REFERENCE_DIRECT_ONLY: "DI" alone (core/shared/direct_integrator.h, the
// Embree reference's direct-lighting mode), the path tracer a DI-only
// realtime output is compared with at equal time (replay/equal_time.h).
#version 460
#extension GL_GOOGLE_include_directive : require
// The truth decodes normal maps as glTF says, whatever the realtime profile
// compiled the other passes with (texture_sampling.h NORMAL_MAP_DECODE).
#undef NORMAL_MAP_DECODE
#define NORMAL_MAP_DECODE 2
#include "gpu/shaders/scene_bindings.glsl"
#ifdef REFERENCE_DIRECT_ONLY
#include "core/shared/direct_integrator.h"
#endif

#ifndef REFERENCE_MAX_BOUNCES
#error "REFERENCE_MAX_BOUNCES must be defined (gpu/passes/reference_path_trace.cpp)"
#endif

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_REFERENCE_A) buffer ReferenceA { vec4 reference_a[]; };
layout(std430, set = 0, binding = BINDING_REFERENCE_B) buffer ReferenceB { vec4 reference_b[]; };
layout(std430, set = 0, binding = BINDING_REFERENCE_NONFINITE) buffer Nonfinite { uint nonfinite_samples; };

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  uint seed = frame.resolution_frame.w;
  vec3 origin = vec3(frame.camera.position);
  vec3 dir = camera_ray_direction(frame.camera, pixel, resolution);

  vec3 background = vec3(0.0);
#ifdef REFERENCE_BACKGROUND
  // Seen where the camera ray misses, never lighting anything (as the Embree
  // reference adds it).
  Hit primary;
  if (!trace_closest(origin, dir, RAY_TMAX, primary)) background = REFERENCE_BACKGROUND;
#endif
  vec4 sum_a = vec4(0.0);
  vec4 sum_b = vec4(0.0);
  uint bad = 0u;
  for (uint s = 0u; s < frame.counts.z; ++s) {
    uint sample_index = frame.counts.w + s;
    uint rng = rng_seed(seed, RNG_DOMAIN_GPU_REFERENCE, index, sample_index);
#ifdef REFERENCE_DIRECT_ONLY
    vec3 radiance = direct_trace(origin, dir, rng) + background;
#else
    vec3 radiance = path_trace(origin, dir, rng, uint(REFERENCE_MAX_BOUNCES)) + background;
#endif
    if (any(isnan(radiance)) || any(isinf(radiance))) {
      ++bad;
      radiance = vec3(0.0);  // the sample still counts: dropping it would bias the mean up
    }
    if ((sample_index & 1u) == 0u)
      sum_a += vec4(radiance, 1.0);
    else
      sum_b += vec4(radiance, 1.0);
  }
  reference_a[index] += sum_a;
  reference_b[index] += sum_b;
  if (bad > 0u) atomicAdd(nonfinite_samples, bad);
}
