// ReSTIR DI, dispatch 2 of 2 (docs/design.md §3 step 6): spatial reuse of one
// neighbour's reservoir (a random pixel in a DI_SPATIAL_RADIUS disk, up to
// DI_SPATIAL_TRIES tries for one that passes pixel_dissimilar), merged with
// this pixel's; the result is stored for next frame; then shading.
//
// Visibility order (DI_VISIBILITY_FINAL):
//   1 (0.18): store the merged reservoir without a new ray; trace the final
//     sample's shadow ray for shading only (not fed forward).
//   0 (0.17): trace a ray to the spatial sample before merging, fold it into
//     that sample's W, store the result (fed forward); shade without a ray.
//   DI_VISIBILITY_FINAL_STORED (Bevy #21649 to #22033): the final ray's
//     result folded into the stored W (fed forward) and shading with it.
// DI_MIS_VISIBILITY 1 (Bevy main): the cross targets p_c(x_o) and p_o(x_c)
// carry the sample's visibility from the pixel that evaluates them (two rays)
// and the merge uses defensive balance MIS.
//
// Output: emitted radiance of the surface + the reservoir's sample shaded with
// the full BRDF (core/shared/direct_integrator.h defines "DI" the same way),
// or its diffuse lobe alone at alpha ≤ DI_SPECULAR_HANDOVER_ALPHA, where
// specular GI takes the specular lobe (Solari 0.18+; negative: never); or
// with DI_SHADING_BASE_OVER_PI (0.17) base_color/π, metallic ignored;
// escaped camera rays see the directional lights' discs.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/shaders/di_common.glsl"
#include "gpu/shaders/spatial_neighbour.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_DI_OUTPUT) writeonly buffer Output { vec4 di_output[]; };
layout(std430, set = 0, binding = BINDING_DI_ACCUMULATION) buffer Accumulation { vec4 di_accumulation[]; };

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  uint chain = gl_GlobalInvocationID.z;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  uint pixels = resolution.x * resolution.y;
  uint slot = chain * pixels + index;
  DiPixel d = di_pixel(pixel);
  vec3 color = vec3(0.0);

  if (!d.hit) {
    color = escaped_radiance(-d.view, 0.0);
#ifdef DI_BACKGROUND
    // Bevy's ClearColor, shown from 0.18 on (#21350); 0.17 wrote black here
    // (v0.17.0:realtime/restir_di.wgsl:71).
    color += DI_BACKGROUND;
#endif
    stored_reservoirs[slot] = empty_di_reservoir();
  } else {
    uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_DI_SPATIAL + chain, index, frame.resolution_frame.z);
    DiReservoir canonical = mid_reservoirs[slot];

    // Choose the spatial neighbour.
    int neighbour = -1;
    DiPixel n;
    float search_radius = float(DI_SPATIAL_RADIUS);
    for (uint attempt = 0u; attempt < uint(DI_SPATIAL_TRIES); ++attempt) {
#if SPATIAL_RADIUS_HALVING != 0
      // Bevy d1095b0efb (#22617) to 11b81eb1d7^: each refused try halves the disk.
      if (attempt > 0u) search_radius *= 0.5;
#endif
      ivec2 q;
      if (!spatial_neighbour_pixel(pixel, resolution, search_radius, rng, q)) continue;
      DiPixel candidate = di_pixel(uvec2(q));
      if (!candidate.hit || di_dissimilar(d, candidate.position, candidate.ns)) continue;
      neighbour = q.y * int(resolution.x) + q.x;
      n = candidate;
      break;
    }

    if (neighbour >= 0) {
      DiReservoir other = mid_reservoirs[chain * pixels + uint(neighbour)];
      MergeTargets t;
      t.pc_xc = 0.0;
      t.po_xc = 0.0;
      t.po_xo = 0.0;
      t.pc_xo = 0.0;
      if (di_reservoir_valid(canonical)) {
        ResolvedLightSample rc = di_resolve(canonical.light);
        t.pc_xc = di_target_at(rc, d.position, d.ng, d.ns, d.diffuse);
        t.po_xc = di_target_at(rc, n.position, n.ng, n.ns, n.diffuse);
#if DI_MIS_VISIBILITY != 0
        if (t.po_xc > 0.0 && !light_sample_visible(n.position, n.ng, rc)) t.po_xc = 0.0;
#endif
      }
      if (di_reservoir_valid(other)) {
        ResolvedLightSample ro = di_resolve(other.light);
        t.po_xo = di_target_at(ro, n.position, n.ng, n.ns, n.diffuse);
        t.pc_xo = di_target_at(ro, d.position, d.ng, d.ns, d.diffuse);
#if DI_MIS_VISIBILITY != 0
        // Visibility from this pixel in the target: an occluded sample gets
        // no resampling weight (what the fed-forward ray of 0.17 also does).
        if (t.pc_xo > 0.0 && !light_sample_visible(d.position, d.ng, ro)) t.pc_xo = 0.0;
#elif DI_VISIBILITY_FINAL == 0
        if (t.pc_xo > 0.0 && !light_sample_visible(d.position, d.ng, ro)) other.unbiased_contribution_weight = 0.0;
#endif
      }
      MergeResult m = di_merge(canonical, other, t, true, rng_next_float(rng));
      canonical = m.merged;
    }
#ifdef DI_VISIBILITY_FINAL_STORED
    // Bevy between #21649 and #22033 (f94997ca37:realtime/restir_di.wgsl:77-82):
    // the final ray zeroes W before the store, so next frame's reuse reads
    // shadowed samples as worthless (the shading below sees the same W).
    if (di_reservoir_valid(canonical) && !light_sample_visible(d.position, d.ng, di_resolve(canonical.light)))
      canonical.unbiased_contribution_weight = 0.0;
#endif
    stored_reservoirs[slot] = canonical;

#if DI_EMISSIVE_UNEXPOSED != 0
    // Solari 0.17 (v0.17.0:realtime/restir_di.wgsl:89-91) exposed the lighting,
    // then added the emissive: in radiance units the emitter gains 1/exposure.
    color = d.emissive / LIGHT_TILE_EXPOSURE;
#else
    color = d.emissive;
#endif
    if (di_reservoir_valid(canonical) && canonical.unbiased_contribution_weight > 0.0) {
      ResolvedLightSample r = di_resolve(canonical.light);
      LightContribution c = light_contribution(r, d.position, d.ns);
      bool visible = dot(c.wi, d.ng) > 0.0;
#if DI_VISIBILITY_FINAL != 0
      visible = visible && light_sample_visible(d.position, d.ng, r);
#endif
      if (visible) {
        BrdfParams brdf = brdf_params(d.g.base_color_metallic.rgb, d.g.base_color_metallic.a, d.g.emissive_roughness.a,
                                      d.g.motion_reflectance.w, gbuffer_brdf_model(d.g));
        // received_radiance carries cos(receiver)·cos(light)/d²; brdf_eval is the BRDF alone.
        // At alpha ≤ DI_SPECULAR_HANDOVER_ALPHA the specular lobe is specular GI's.
#if DI_SHADING_BASE_OVER_PI != 0
        vec3 f = dot(d.ns, c.wi) > 0.0 ? d.g.base_color_metallic.rgb * INV_PI : vec3(0.0);
#else
        vec3 f = brdf.alpha <= float(DI_SPECULAR_HANDOVER_ALPHA) ? brdf_eval_diffuse(brdf, d.ns, d.view, c.wi)
                                                                  : brdf_eval(brdf, d.ns, d.view, c.wi);
#endif
        color += f * c.received_radiance * canonical.unbiased_contribution_weight;
      }
    }
  }

  if (chain == 0u) {
    DiSurface s;
    s.position_view_z = vec4(d.position, d.hit ? max(d.view_z, 1e-20) : 0.0);
    s.normal = vec4(d.ns, 0.0);
    s.diffuse = vec4(d.diffuse, 0.0);
    surfaces[index] = s;
  }
  di_output[slot] = vec4(color, d.hit ? 1.0 : 0.0);
  if (push.accumulate != 0u) di_accumulation[slot] += vec4(color, 1.0);
}
