// ReSTIR DI, dispatch 1 of 2 (docs/design.md §3 step 6): initial RIS over
// DI_INITIAL_SAMPLES candidates of one light tile (DI_TILE_PER_WORKGROUP 1:
// the 8×8 workgroup's frame-constant tile, Solari; 0: a random tile per pixel
// and frame) (target: luminance of the unshadowed contribution × colour/π,
// DI_TARGET_BASE_COLOR; constant MIS 1/N), a shadow ray on the winner; then
// temporal reuse of last frame's stored reservoir through the motion vector
// (DI_TEMPORAL_PERMUTATION 1: at the reprojected pixel permuted within 4×4
// blocks, and where that gives no valid reservoir at the reprojected pixel
// itself, Solari 0.18, unless DI_TEMPORAL_FALLBACK 0, 0.19; 0: the
// reprojected pixel only, 0.17; off screen, DI_OFFSCREEN_OWN_PIXEL 1 starts
// from the pixel itself, 0.19, 0 takes no history), rejected when
// the surfaces differ (pixel_dissimilar) or its light no longer exists,
// confidence capped at DI_CONFIDENCE_CAP, visibility reused (no ray; with
// DI_MIS_VISIBILITY two rays for the cross MIS targets). Writes the merged
// reservoir for the spatial pass. z indexes the independent chain.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/shaders/di_common.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_LIGHT_TILE_SAMPLES) readonly buffer TileSamples { LightSample tile_samples[]; };
layout(std430, set = 0, binding = BINDING_LIGHT_TILE_PACKED) readonly buffer TilePacked { PackedLightSample tile_packed[]; };
layout(std430, set = 0, binding = BINDING_DI_LIGHT_TRANSLATION) readonly buffer Translation { uint light_translation[]; };

// Last frame's surface and stored reservoir at pixel q, usable for temporal
// reuse when that pixel had a surface similar to this one (pixel_dissimilar)
// and its reservoir holds a sample (Solari's reservoir_valid).
bool di_temporal_candidate(DiPixel d, uint chain, uvec2 q, out DiSurface s, out DiReservoir r) {
  uvec2 resolution = frame.resolution_frame.xy;
  uint q_index = q.y * resolution.x + q.x;
  s = surfaces[q_index];
  r = stored_reservoirs[chain * resolution.x * resolution.y + q_index];
  return s.position_view_z.w > 0.0 && di_reservoir_valid(r) && !di_dissimilar(d, s.position_view_z.xyz, s.normal.xyz);
}

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  uint chain = gl_GlobalInvocationID.z;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  uint slot = chain * resolution.x * resolution.y + index;
  DiPixel d = di_pixel(pixel);
  if (!d.hit || scene_light_count() == 0u) {
    mid_reservoirs[slot] = empty_di_reservoir();
    return;
  }
  uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_DI_INITIAL + chain, index, frame.resolution_frame.z);

  // Initial candidates.
  uint per_chain = uint(LIGHT_TILE_COUNT) * uint(LIGHT_TILE_SAMPLES);
#if DI_TILE_PER_WORKGROUP != 0
  uint tile_start = chain * per_chain + di_workgroup_tile(gl_WorkGroupID.xy, uint(LIGHT_TILE_COUNT)) *
                                            uint(LIGHT_TILE_SAMPLES);
#else
  uint tile_start = chain * per_chain +
                    min(uint(rng_next_float(rng) * float(LIGHT_TILE_COUNT)), uint(LIGHT_TILE_COUNT) - 1u) *
                        uint(LIGHT_TILE_SAMPLES);
#endif
  RisStream ris = ris_begin();
  uint selected = 0xFFFFFFFFu;
  for (uint i = 0u; i < uint(DI_INITIAL_SAMPLES); ++i) {
    uint k = tile_start + min(uint(rng_next_float(rng) * float(LIGHT_TILE_SAMPLES)), uint(LIGHT_TILE_SAMPLES) - 1u);
    ResolvedLightSample r = unpack_light_sample(tile_packed[k], LIGHT_TILE_EXPOSURE, LIGHT_TILE_LOG2_RADIANCE != 0);
    LightContribution c = light_contribution(r, d.position, d.ns);
    float target = dot(c.wi, d.ng) > 0.0 ? di_target(c, d.diffuse) : 0.0;
    float weight = target * c.inverse_pdf / float(DI_INITIAL_SAMPLES);
    if (ris_update(ris, weight, target, rng_next_float(rng))) selected = k;
  }
  DiReservoir canonical = empty_di_reservoir();
  canonical.confidence_weight = 1.0;
  if (selected != 0xFFFFFFFFu) {
    canonical.light = tile_samples[selected];
    canonical.unbiased_contribution_weight = ris_contribution_weight(ris);
#if DI_INITIAL_VISIBILITY != 0
    // Solari's step 2: an occluded winner keeps its sample but gets W = 0, and
    // that W is stored and reused. A neighbour that sees the light is then
    // never given the sample, while the balance heuristic still counts this
    // pixel's share of it: direct light comes out dark near every shadow edge
    // (README, "DI bias"). DI_INITIAL_VISIBILITY 0 leaves the test to shading.
    ResolvedLightSample r = unpack_light_sample(tile_packed[selected], LIGHT_TILE_EXPOSURE, LIGHT_TILE_LOG2_RADIANCE != 0);
    if (!light_sample_visible(d.position, d.ng, r)) canonical.unbiased_contribution_weight = 0.0;
#endif
  }

  // Temporal reuse.
  ivec2 q;
  if (push.history_valid != 0u) {
    if (temporal_source_pixel(pixel, d.g.motion_reflectance, resolution, DI_OFFSCREEN_OWN_PIXEL != 0, q)) {
      DiSurface s;
      DiReservoir temporal;
#if DI_TEMPORAL_PERMUTATION != 0
      uvec2 permuted = di_permute_pixel(uvec2(q), di_permutation_random(frame.resolution_frame.z), resolution);
      bool usable = di_temporal_candidate(d, chain, permuted, s, temporal);
#if DI_TEMPORAL_FALLBACK != 0
      // Where the permuted pixel gives no valid reservoir (object edges), the
      // reprojected pixel itself (0.18; 0.19 has no fallback).
      if (!usable) usable = di_temporal_candidate(d, chain, uvec2(q), s, temporal);
#endif
#else
      bool usable = di_temporal_candidate(d, chain, uvec2(q), s, temporal);
#endif
      if (usable) {
        uint id = temporal.light.light_id < push.previous_light_count ? light_translation[temporal.light.light_id]
                                                                      : LIGHT_ID_GONE;
        usable = id != LIGHT_ID_GONE;
        temporal.light.light_id = id;
      }
      if (usable) {
        temporal.confidence_weight = min(temporal.confidence_weight, float(DI_CONFIDENCE_CAP));
        vec3 prev_position = s.position_view_z.xyz;
        vec3 prev_ng = s.normal.xyz;  // the previous surface's normal stands in for both of its normals
        MergeTargets t;
        t.pc_xc = 0.0;
        t.po_xc = 0.0;
        if (di_reservoir_valid(canonical)) {
          ResolvedLightSample rc = di_resolve(canonical.light);
          t.pc_xc = di_target_at(rc, d.position, d.ng, d.ns, d.diffuse);
          t.po_xc = di_target_at(rc, prev_position, prev_ng, prev_ng, s.diffuse.rgb);
#if DI_MIS_VISIBILITY != 0
          // Did this frame's sample light the history's surface? Bevy main
          // since #25046 asks last frame's scene (TRACE_PREVIOUS_SCENE,
          // restir_di.temporal_mis_scene previous_frame); before, this
          // frame's: where an occluder just moved away the sample looks
          // visible there too, the shadowed history keeps its weight and the
          // old shadow lingers for frames (the shadow_lag check).
#ifdef TRACE_PREVIOUS_SCENE
          if (t.po_xc > 0.0 && !light_sample_visible_previous_scene(prev_position, prev_ng, rc)) t.po_xc = 0.0;
#else
          if (t.po_xc > 0.0 && !light_sample_visible(prev_position, prev_ng, rc)) t.po_xc = 0.0;
#endif
#endif
        }
        ResolvedLightSample ro = di_resolve(temporal.light);
        t.po_xo = di_target_at(ro, prev_position, prev_ng, prev_ng, s.diffuse.rgb);
        t.pc_xo = di_target_at(ro, d.position, d.ng, d.ns, d.diffuse);
#if DI_MIS_VISIBILITY != 0
        if (t.pc_xo > 0.0 && !light_sample_visible(d.position, d.ng, ro)) t.pc_xo = 0.0;
#endif
        MergeResult m = di_merge(canonical, temporal, t, false, rng_next_float(rng));
        canonical = m.merged;
      }
    }
  }
  mid_reservoirs[slot] = canonical;
}
