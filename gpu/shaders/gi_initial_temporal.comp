// ReSTIR GI, dispatch 1 of 2 (docs/design.md §3 step 7): the initial sample, one
// uniform-hemisphere ray; a miss or an emissive hit gives an empty reservoir
// (confidence 0 under GI_EMPTY_NO_CONFIDENCE, as Solari: v0.18.0
// realtime/restir_gi.wgsl:97-105; else M = 1), else radiance =
// secondary_hit_radiance(hit) (hit_radiance.glsl; GI_HIT_RADIANCE 2: the world
// cache, Solari's query), W = 2π, M = 1. Then temporal reuse of last frame's
// stored reservoir through the motion vector, the reprojected pixel permuted
// within 4×4 blocks (GI_TEMPORAL_PERMUTATION) with GI_TEMPORAL_FALLBACK when
// the permuted pixel is unusable, rejected when the surfaces differ,
// confidence capped at GI_CONFIDENCE_CAP, merged with jacobians (gi_merge).
// z indexes the chain.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/shaders/gi_common.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_STORED) readonly buffer Stored { GiReservoir stored_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_MID) writeonly buffer Mid { GiReservoir mid_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_GI_SURFACES) readonly buffer Surfaces { GiSurface surfaces[]; };
layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_HISTORY) readonly buffer History { GiReservoir history_reservoirs[]; };

#ifndef GI_INITIAL_SAMPLES
#define GI_INITIAL_SAMPLES 1
#endif

#if GI_EMPTY_NO_CONFIDENCE != 0
const float GI_EMPTY_CONFIDENCE = 0.0;
#else
const float GI_EMPTY_CONFIDENCE = 1.0;
#endif

// Whether a hit counts as an emitter, which GI leaves to DI (empty sample).
bool gi_hit_emissive(SurfacePoint s, bool front) {
#if GI_EMISSIVE_TEST == 1
  // Solari 0.17/0.18's all(emissive != 0) (v0.18.0 realtime/restir_gi.wgsl:103):
  // an emitter with a zero channel is treated as a reflector, on either face.
  return all(notEqual(s.emissive, vec3(0.0)));
#elif GI_EMISSIVE_TEST == 2
  return any(notEqual(s.emissive, vec3(0.0)));  // 0.19 (v0.19.0 :102)
#else
  return front && max3(s.emissive) > 0.0;
#endif
}

// Last frame's reservoir at pixel q if its surface is similar to d's.
bool gi_temporal_candidate(GiPixel d, ivec2 q, uint chain, out GiReservoir r, out GiSurface s) {
  uvec2 resolution = frame.resolution_frame.xy;
  uint q_index = uint(q.y) * resolution.x + uint(q.x);
  s = surfaces[q_index];
#if GI_TEMPORAL_HISTORY != 0
  r = history_reservoirs[chain * resolution.x * resolution.y + q_index];
#else
  r = stored_reservoirs[chain * resolution.x * resolution.y + q_index];
#endif
  return s.position_view_z.w > 0.0 && !gi_dissimilar(d, s.position_view_z.xyz, s.normal.xyz);
}

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  uint chain = gl_GlobalInvocationID.z;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  uint pixels = resolution.x * resolution.y;
  uint slot = chain * pixels + index;
  GiPixel d = gi_pixel(pixel);
  if (!d.hit || gi_skips_pixel(d)) {
    mid_reservoirs[slot] = empty_gi_reservoir(0.0);
    return;
  }
  uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_GI_INITIAL + chain, index, frame.resolution_frame.z);

  // Initial sample.
  GiReservoir canonical = empty_gi_reservoir(GI_EMPTY_CONFIDENCE);
#if GI_INITIAL_SAMPLES == 1
  vec3 dir = to_world(sample_uniform_hemisphere(rng_next_vec2(rng)), d.ns);
  if (dot(dir, d.ng) > 0.0) {
    Hit hit;
    if (trace_closest(offset_ray_origin(d.position, d.ng), dir, float(GI_RAY_TMAX), hit)) {
      SurfacePoint s = surface_at_hit(hit);
      bool front = dot(dir, s.geometric_normal) < 0.0;
      if (!gi_hit_emissive(s, front)) {
        vec3 ng = front ? s.geometric_normal : -s.geometric_normal;
        vec3 ns = dot(s.shading_normal, ng) < 0.0 ? -s.shading_normal : s.shading_normal;
        canonical.sample_position = vec4(s.position, 1.0);
        canonical.sample_normal.xyz = gi_sample_normal(s, ng);
        canonical.radiance =
            vec4(secondary_hit_radiance(hit, s, ng, ns, dir, gi_pixel_query(gi_cache_query_id(0u, chain, index), true), rng),
                 TWO_PI);
      }
    }
  }
#else
  // restir_gi.initial_samples > 1 (a harness knob; Solari traces one ray,
  // v0.18.0 realtime/restir_gi.wgsl:91-109): resampled importance sampling
  // over N such rays, each weighted by its target over the uniform pdf; the
  // winner's contribution weight is the mean weight over its target. The
  // reservoir keeps confidence 1, as Solari's initial one (and ReSTIR DI's
  // 8-candidate one) has. Each candidate's cache query has an id of its own
  // (blocks 2.. after specular GI's; WorldCacheSettings::external_queries_per_pixel
  // counts them): with one id shared, a candidate's request to insert a new
  // cell could be dropped, and its empty cell read as black (indirect light
  // 10 % dark in the Cornell box at N = 4).
  float weight_sum = 0.0;
  for (uint i = 0u; i < uint(GI_INITIAL_SAMPLES); ++i) {
    vec3 dir = to_world(sample_uniform_hemisphere(rng_next_vec2(rng)), d.ns);
    if (dot(dir, d.ng) <= 0.0) continue;
    Hit hit;
    if (!trace_closest(offset_ray_origin(d.position, d.ng), dir, float(GI_RAY_TMAX), hit)) continue;
    SurfacePoint s = surface_at_hit(hit);
    bool front = dot(dir, s.geometric_normal) < 0.0;
    if (gi_hit_emissive(s, front)) continue;
    vec3 ng = front ? s.geometric_normal : -s.geometric_normal;
    vec3 ns = dot(s.shading_normal, ng) < 0.0 ? -s.shading_normal : s.shading_normal;
    vec3 radiance =
        secondary_hit_radiance(hit, s, ng, ns, dir, gi_pixel_query(gi_cache_query_id(i == 0u ? 0u : 1u + i, chain, index), true), rng);
    float w = gi_target(radiance * d.target, s.position, d.position, d.ns) * TWO_PI;
    if (!(w > 0.0)) continue;
    weight_sum += w;
    if (rng_next_float(rng) * weight_sum <= w) {
      canonical.sample_position = vec4(s.position, 1.0);
      canonical.sample_normal.xyz = gi_sample_normal(s, ng);
      canonical.radiance.rgb = radiance;
    }
  }
  if (weight_sum > 0.0) {
    float target = gi_target(canonical.radiance.rgb * d.target, canonical.sample_position.xyz, d.position, d.ns);
    canonical.radiance.w = weight_sum / (float(GI_INITIAL_SAMPLES) * target);
  }
#endif

  // Temporal reuse (GI_NO_TEMPORAL_REUSE: none; restir_gi.temporal_reuse
  // false, a harness-only switch for the GI noise breakdown of docs/speed.md).
#ifdef GI_NO_TEMPORAL_REUSE
#define GI_HISTORY_VALID 0u
#else
#define GI_HISTORY_VALID push.history_valid
#endif
  ivec2 q;
  if (GI_HISTORY_VALID != 0u) {
    if (temporal_source_pixel(pixel, d.motion, resolution, GI_OFFSCREEN_OWN_PIXEL != 0, q)) {
      GiReservoir temporal;
      GiSurface s;
#if GI_TEMPORAL_PERMUTATION != 0
      // Solari 0.17 tries up to 4 permutations and takes the first similar
      // surface (v0.17.0 realtime/restir_gi.wgsl:135-151); 0.18 tries one and
      // falls back to the unpermuted pixel when its surface differs or its
      // reservoir has no radiance (v0.18.0 :136-142).
      const uint tries = GI_TEMPORAL_FALLBACK == 2 ? 4u : 1u;
      bool found = false;
      for (uint i = 0u; i < tries && !found; ++i)
        found = gi_temporal_candidate(d, gi_permute_pixel(q, push.permutation + i, ivec2(resolution)), chain, temporal, s);
#if GI_TEMPORAL_FALLBACK == 1
      if (!found || all(equal(temporal.radiance.rgb, vec3(0.0))))
        found = gi_temporal_candidate(d, q, chain, temporal, s);
#endif
#else
      bool found = gi_temporal_candidate(d, q, chain, temporal, s);
#endif
#if GI_TEMPORAL_EDGE_STATS != 0
      if (chain == 0u && gi_pixel_at_edge(d, pixel)) {
        atomicAdd(gi_stats.temporal_edge_pixels, 1u);
        if (found) atomicAdd(gi_stats.temporal_edge_reused, 1u);
      }
#endif
      if (found) {
        temporal.sample_position.w = min(temporal.sample_position.w, float(GI_CONFIDENCE_CAP));
        // Last frame's surface is this pixel's (or a permuted neighbour's, at most
        // 3 px away, similar by pixel_dissimilar): visibility is assumed, as in Solari.
        canonical = gi_merge(canonical, d.position, d.ns, d.target, temporal, s.position_view_z.xyz, s.normal.xyz,
                             gi_target_colour(s.base_color.rgb), true, rng_next_float(rng));
      }
    }
  }
  mid_reservoirs[slot] = canonical;
}
