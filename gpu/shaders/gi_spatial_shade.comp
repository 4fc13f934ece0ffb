// ReSTIR GI, dispatch 2 of 2 (docs/design.md §3 step 7): spatial reuse of one
// neighbour (a random pixel in a GI_SPATIAL_RADIUS disk, up to GI_SPATIAL_TRIES
// tries for a similar surface), merged with jacobians. Visibility:
// - GI_VISIBILITY_FINAL (Solari 0.18, v0.18.0 realtime/restir_gi.wgsl:66-82):
//   the merge ignores visibility and is stored for next frame and for
//   specular GI; one ray to the final sample scales this frame's shading only.
// - else (Solari 0.17, v0.17.0 :170-171): the neighbour's sample is tested
//   from this pixel before the merge, and the result is stored.
// Then diffuse shading, GI = brdf · radiance · W · cos with brdf
// Bevy's evaluate_diffuse_brdf under the material model (GI_SHADING_DIFFUSE,
// 0.18: base·(1 − metallic)/π; 0.19: that, Fresnel-layered) or base/π (0.17).
// Also writes this pixel's surface for next frame's temporal reuse, and
// counts non-finite reservoirs and output pixels (GiStats).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/shaders/gi_common.glsl"
#include "gpu/shaders/spatial_neighbour.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_STORED) writeonly buffer Stored { GiReservoir stored_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_MID) readonly buffer Mid { GiReservoir mid_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_GI_SURFACES) writeonly buffer Surfaces { GiSurface surfaces[]; };
layout(std430, set = 0, binding = BINDING_GI_OUTPUT) writeonly buffer Output { vec4 gi_output[]; };
layout(std430, set = 0, binding = BINDING_GI_ACCUMULATION) buffer Accumulation { vec4 gi_accumulation[]; };
layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_HISTORY) writeonly buffer History { GiReservoir history_reservoirs[]; };

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  uint chain = gl_GlobalInvocationID.z;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  uint pixels = resolution.x * resolution.y;
  uint slot = chain * pixels + index;
  GiPixel d = gi_pixel(pixel);
  vec3 color = vec3(0.0);

  if (!d.hit || gi_skips_pixel(d)) {
    stored_reservoirs[slot] = empty_gi_reservoir(0.0);
#if GI_TEMPORAL_HISTORY != 0
    history_reservoirs[slot] = empty_gi_reservoir(0.0);
#endif
  } else {
    uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_GI_SPATIAL + chain, index, frame.resolution_frame.z);
    GiReservoir canonical = mid_reservoirs[slot];
#if GI_TEMPORAL_HISTORY != 0
    history_reservoirs[slot] = canonical;  // next frame's history: the temporal merge alone
#endif

    int neighbour = -1;
    GiPixel n;
    float search_radius = float(GI_SPATIAL_RADIUS);
    for (uint attempt = 0u; attempt < uint(GI_SPATIAL_TRIES); ++attempt) {
#if SPATIAL_RADIUS_HALVING != 0
      // Bevy d1095b0efb (#22617) to 11b81eb1d7^: each refused try halves the disk.
      if (attempt > 0u) search_radius *= 0.5;
#endif
      ivec2 q;
      if (!spatial_neighbour_pixel(pixel, resolution, search_radius, rng, q)) continue;
      GiPixel candidate = gi_pixel(uvec2(q));
      if (!candidate.hit || gi_dissimilar(d, candidate.position, candidate.ns)) continue;
      neighbour = q.y * int(resolution.x) + q.x;
      n = candidate;
      break;
    }
#if GI_PATH_COUNTERS != 0
    if (chain == 0u) {
      atomicAdd(gi_counters.spatial_pixels, 1u);
      if (neighbour >= 0) atomicAdd(gi_counters.spatial_found, 1u);
    }
#endif
    if (neighbour >= 0) {
      GiReservoir other = mid_reservoirs[chain * pixels + uint(neighbour)];
#if GI_VISIBILITY_FINAL == 0
      // The neighbour's point must be visible from here (its confidence still
      // counts), and this pixel's from the neighbour for the MIS weights
      // (GI_CONSISTENT_MIS; 0: Solari's visibility-free weights, dark).
      if (gi_reservoir_valid(other) && !gi_point_visible(d.position, d.ng, other.sample_position.xyz))
        other.radiance.w = 0.0;
#endif
      bool canonical_visible_at_other = true;
#if GI_CONSISTENT_MIS != 0 && GI_VISIBILITY_FINAL == 0
      // (Under GI_VISIBILITY_FINAL neither target carries visibility, so the
      // weights already sum to one; the final ray handles occlusion.)
      if (gi_reservoir_valid(canonical))
        canonical_visible_at_other = gi_point_visible(n.position, n.ng, canonical.sample_position.xyz);
#endif
      canonical = gi_merge(canonical, d.position, d.ns, d.target, other, n.position, n.ns, n.target,
                           canonical_visible_at_other, rng_next_float(rng));
    }
    if (!gi_reservoir_finite(canonical)) atomicAdd(gi_stats.nonfinite_reservoirs, 1u);
    bool shade = gi_reservoir_valid(canonical);
#if GI_VISIBILITY_FINAL_STORED != 0
    // Bevy between #21649 and #21919 (37023731b9^:realtime/restir_gi.wgsl:71-79):
    // the final ray zeroes the stored sample's radiance, which next frame
    // reuses as dark, while this frame shades the merged radiance unshadowed.
    if (shade && !gi_point_visible(d.position, d.ng, canonical.sample_position.xyz)) {
      stored_reservoirs[slot] = canonical;
      stored_reservoirs[slot].radiance.rgb = vec3(0.0);
    } else {
      stored_reservoirs[slot] = canonical;
    }
#else
#if GI_VISIBILITY_FINAL != 0
    if (shade) shade = gi_point_visible(d.position, d.ng, canonical.sample_position.xyz);
#endif
    stored_reservoirs[slot] = canonical;
#endif
    if (shade) {
      vec3 wi = normalize(canonical.sample_position.xyz - d.position);
#if GI_SHADING_DIFFUSE != 0
      vec3 brdf = brdf_eval_diffuse(d.brdf, d.ns, d.view, wi);
#else
      vec3 brdf = d.base_color * INV_PI;
#endif
      color = brdf * canonical.radiance.rgb * canonical.radiance.w * max(dot(d.ns, wi), 0.0);
#if GI_COSINE_TWICE != 0
      // Bevy 11b81eb1d7^:realtime/restir_gi.wgsl:248,83-86: the merge returns
      // radiance · cos and #22468's diffuse BRDF multiplies by n·l again.
      color *= max(dot(d.ns, wi), 0.0);
#endif
    }
  }

  if (chain == 0u) {
    GiSurface s;
    s.position_view_z = vec4(d.position, d.hit ? max(d.view_z, 1e-20) : 0.0);
    s.normal = vec4(d.ns, 0.0);
    s.base_color = vec4(d.base_color, d.metallic);
    surfaces[index] = s;
  }
  if (!(gi_finite(color.r) && gi_finite(color.g) && gi_finite(color.b))) atomicAdd(gi_stats.nonfinite_output, 1u);
  gi_output[slot] = vec4(color, d.hit ? 1.0 : 0.0);
  if (push.accumulate != 0u) gi_accumulation[slot] += vec4(color, 1.0);
}
