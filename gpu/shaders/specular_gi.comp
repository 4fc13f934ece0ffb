// Specular GI (docs/design.md §3 step 8; Bevy v0.18.0 realtime/specular_gi.wgsl): the
// specular lobe's indirect light at each pixel.
// - alpha > SPECULAR_REUSE_ROUGHNESS: reuse this frame's final GI reservoir
//   (its direction and radiance · W) with the specular BRDF.
// - else sample GGX with bounded VNDF (the mirror special case at alpha ≤
//   0.001) and trace_glossy_path: up to SPECULAR_MAX_BOUNCES bounces;
//   emissive hits count from the second vertex on (DI owns the first; at
//   alpha ≤ SPECULAR_HANDOVER_ALPHA DI shades only its diffuse lobe and the
//   first hit's emission counts here with weight 1, as Solari 0.18+), NEE
//   at non-mirror vertices, MIS between the two by the power heuristic
//   (SPECULAR_POWER_MIS, Solari's) or the balance heuristic; the path ends in
//   end_path_radiance (GI_HIT_RADIANCE 2: the world cache, pixel-rooted, as
//   Solari) when its spread outgrows the cell (SPECULAR_PATH_SPREAD, Solari
//   0.18) or else at the first hit rougher than SPECULAR_REUSE_ROUGHNESS;
//   hit_radiance.glsl.
// The primary surface's roughness is clamped by SPECULAR_MIN_PERCEPTUAL_ROUGHNESS
// (brdf.min_perceptual_roughness; 0: no clamp, NaN at zero roughness).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/scene_bindings.glsl"
#if GI_PATH_COUNTERS != 0
// This invocation's closest-hit rays along its glossy path (the ray_budget
// check): counted here and in secondary_hit.h's loop, added once per pixel.
uint glossy_segments_traced = 0u;
#define GLOSSY_SEGMENT_TRACED() ++glossy_segments_traced
#else
#define GLOSSY_SEGMENT_TRACED()
#endif
#ifdef SPECULAR_MIRROR_THROUGHPUT_BRDF
// Solari 0.19's mirror-vertex throughput (secondary_hit.h), this pass's only.
#define HIT_MIRROR_THROUGHPUT_BRDF 1
#endif
#include "gpu/shaders/gi_common.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_STORED) readonly buffer Stored { GiReservoir stored_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_SPECULAR_OUTPUT) writeonly buffer Output { vec4 specular_output[]; };
layout(std430, set = 0, binding = BINDING_SPECULAR_ACCUMULATION) buffer Accumulation { vec4 specular_accumulation[]; };

// Radiance arriving at `position` along `dir`, without what DI owns (the
// first hit's emission, escaped light): glossy_path_radiance from the first hit.
vec3 trace_glossy_path(vec3 position, vec3 ng, vec3 dir, uint query_id, GlossyPathEnd path_end, inout uint rng) {
  Hit first;  // traced by glossy_path_radiance_from
  return glossy_path_radiance_from(true, first, offset_ray_origin(position, ng), dir, gi_pixel_query(query_id, false),
                                   path_end, rng);
}

#if SPECULAR_CACHE_EVERY_VERTEX != 0
// Solari's glossy path before #21907 (6c22c9b444^:realtime/specular_gi.wgsl:
// 71-105), as the specular GI of #21355 shipped on main: up to three
// vertices, each adding the world cache's diffuse light (end_path_radiance)
// while the path goes on along the GGX lobe (VNDF-sampled, weighted with the
// full BRDF); it ends after a hit rougher than alpha 0.1, not at the first;
// no emission and no NEE anywhere.
vec3 trace_glossy_path_cache_every_vertex(vec3 position, vec3 ng, vec3 dir, uint query_id, inout uint rng) {
  CacheQuery q = gi_pixel_query(query_id, false);
  vec3 radiance = vec3(0.0);
  vec3 throughput = vec3(1.0);
  vec3 origin = offset_ray_origin(position, ng);
  for (uint vertex = 0u; vertex < 3u; ++vertex) {
    Hit hit;
    GLOSSY_SEGMENT_TRACED();
    if (!trace_closest(origin, dir, RAY_TMAX, hit)) break;
    SurfacePoint s = surface_at_hit(hit);
    vec3 hng = dot(dir, s.geometric_normal) < 0.0 ? s.geometric_normal : -s.geometric_normal;
    vec3 hns = dot(s.shading_normal, hng) < 0.0 ? -s.shading_normal : s.shading_normal;
    vec3 v = -dir;
    radiance += throughput * end_path_radiance(s, hng, hns, v, hit.t, q, rng);
    BrdfParams brdf = surface_brdf(s);
    if (brdf.alpha > 0.1 && vertex != 0u) break;
    q.first_bounce = 0u;
    vec3 l = to_world(sample_ggx_bounded_vndf(from_world(v, hns), brdf.alpha, rng_next_vec2(rng)), hns);
    if (dot(l, hng) <= 0.0 || dot(l, hns) <= 0.0) break;
    float pdf = ggx_bounded_vndf_pdf(from_world(v, hns), from_world(l, hns), brdf.alpha);
    throughput *= brdf_eval(brdf, hns, v, l) * (max(dot(hns, l), 0.0) / pdf);
    origin = offset_ray_origin(s.position, hng);
    dir = l;
  }
  return radiance;
}
#endif

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  uint chain = gl_GlobalInvocationID.z;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  uint slot = chain * resolution.x * resolution.y + index;
  GiPixel d = gi_pixel(pixel);
  vec3 color = vec3(0.0);
  if (d.hit) {
    uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_SPECULAR + chain, index, frame.resolution_frame.z);
    // The material model's lobe at this profile's clamp (0: none, NaN at zero roughness).
    BrdfParams brdf = d.brdf;
    brdf.alpha = specular_alpha(d.perceptual_roughness, float(SPECULAR_MIN_PERCEPTUAL_ROUGHNESS));
    brdf.perceptual_roughness = sqrt(brdf.alpha);
    float alpha = brdf.alpha;
    if (alpha > float(SPECULAR_REUSE_ROUGHNESS)) {
      GiReservoir r = stored_reservoirs[slot];
      if (gi_reservoir_valid(r)) {
        vec3 wi = normalize(r.sample_position.xyz - d.position);
        color = specular_lobe(brdf, d.ns, d.view, wi) * max(dot(d.ns, wi), 0.0) * r.radiance.rgb * r.radiance.w;
      }
    } else if (brdf_has_specular(brdf)) {
      vec3 wi = to_world(sample_ggx_bounded_vndf(from_world(d.view, d.ns), alpha, rng_next_vec2(rng)), d.ns);
      // DI left this surface's specular lobe, first hit's emission included, to us.
      float first_emission = alpha <= float(SPECULAR_HANDOVER_ALPHA) ? 1.0 : 0.0;
      GlossyPathEnd path_end = glossy_path_end(-1.0, 0.0, first_emission);
#if SPECULAR_PATH_SPREAD != 0 && GI_HIT_RADIANCE == 2
      vec3 to_camera = frame.camera.position.xyz - d.position;
      path_end.spread_a0 = 0.03 * dot(to_camera, to_camera) / (4.0 * PI * max(dot(d.view, d.ns), 1e-6));
      path_end.first_pdf = alpha <= SPECULAR_MIRROR_ALPHA
                               ? 1e30
                               : ggx_bounded_vndf_pdf(from_world(d.view, d.ns), from_world(wi, d.ns), alpha);
#endif
#if SPECULAR_PATH_LONG_RAY != 0 && GI_HIT_RADIANCE == 2
      path_end.path_roughness = alpha;
#endif
#if SPECULAR_CACHE_EVERY_VERTEX != 0
      if (dot(wi, d.ng) > 0.0 && dot(wi, d.ns) > 0.0)
        color = specular_sample_weight(brdf, d.ns, d.view, wi) *
                trace_glossy_path_cache_every_vertex(d.position, d.ng, wi, gi_cache_query_id(1u, chain, index), rng);
#else
      if (dot(wi, d.ng) > 0.0 && dot(wi, d.ns) > 0.0)
        color = specular_sample_weight(brdf, d.ns, d.view, wi) *
                trace_glossy_path(d.position, d.ng, wi, gi_cache_query_id(1u, chain, index), path_end, rng);
#endif
    }
  }
  if (!(gi_finite(color.r) && gi_finite(color.g) && gi_finite(color.b))) atomicAdd(gi_stats.nonfinite_output, 1u);
#if GI_PATH_COUNTERS != 0
  if (chain == 0u && glossy_segments_traced > 0u) {
    atomicAdd(gi_counters.specular_paths, 1u);
    atomicAdd(gi_counters.specular_segments, glossy_segments_traced);
  }
#endif
  specular_output[slot] = vec4(color, d.hit ? 1.0 : 0.0);
  if (push.accumulate != 0u) specular_accumulation[slot] += vec4(color, 1.0);
}
