// What both ReSTIR DI passes share: bindings, the pixel's surface from the
// G-buffer, and the target function of a reservoir's sample at a surface.
// Included after scene_bindings.glsl.
//
// Defines: LIGHT_TILE_* (light_tiles.comp), DI_INITIAL_SAMPLES,
// DI_CONFIDENCE_CAP, DI_SPATIAL_RADIUS, DI_SPATIAL_TRIES, DI_PLANE_TOLERANCE,
// DI_NORMAL_MIN_DOT, DI_BALANCE_MIS (1: balance heuristic, 0: constant),
// DI_VISIBILITY_FINAL (1: 0.18 order, 0: 0.17 spatial ray fed forward),
// DI_INITIAL_VISIBILITY (1: the initial winner's shadow ray zeroes its stored W),
// DI_MIS_VISIBILITY (1: visibility in the cross MIS targets, defensive spatial
// MIS), DI_TARGET_BASE_COLOR (1: target colour base, 0: base · (1 − metallic)),
// DI_TEMPORAL_PERMUTATION (1: permuted reprojection, point fallback),
// DI_TILE_PER_WORKGROUP (1: one frame-constant tile per 8×8 workgroup),
// DI_REUSE_RADIANCE_SCENE (1: reused samples re-resolved in full precision).
#include "core/shared/light_tiles.h"
#include "core/shared/reservoir.h"
#include "core/shared/restir_di.h"
#include "gpu/shaders/di_bindings.h"
#include "gpu/shaders/gbuffer.h"
#include "core/shared/light_sampling.h"

layout(push_constant) uniform Push { DiPushConstants push; };

layout(std430, set = 0, binding = BINDING_GBUFFER) readonly buffer GBuffer { GBufferTexel gbuffer[]; };
layout(std430, set = 0, binding = BINDING_DI_RESERVOIRS_STORED) buffer Stored { DiReservoir stored_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_DI_RESERVOIRS_MID) buffer Mid { DiReservoir mid_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_DI_SURFACES) buffer Surfaces { DiSurface surfaces[]; };

struct DiPixel {
  bool hit;
  vec3 position;
  vec3 ng;        // geometric normal on the camera's side
  vec3 ns;        // shading normal on that side
  vec3 view;      // unit, towards the camera
  float view_z;
  vec3 diffuse;   // the target's colour (DI_TARGET_BASE_COLOR)
  vec3 emissive;  // front face only
  uint material_index_unused;
  GBufferTexel g;
};

DiPixel di_pixel(uvec2 pixel) {
  uvec2 resolution = frame.resolution_frame.xy;
  DiPixel d;
  d.g = gbuffer[pixel.y * resolution.x + pixel.x];
  d.hit = d.g.geometric_normal.w > 0.0;
  vec3 dir = camera_ray_direction(frame.camera, pixel, resolution);
  d.position = d.g.position_depth.xyz;
  bool front = dot(dir, d.g.geometric_normal.xyz) < 0.0;
  d.ng = front ? d.g.geometric_normal.xyz : -d.g.geometric_normal.xyz;
  d.ns = dot(d.g.shading_normal.xyz, d.ng) < 0.0 ? -d.g.shading_normal.xyz : d.g.shading_normal.xyz;
  d.view = -dir;
  d.view_z = dot(d.position - frame.camera.position.xyz, normalize(frame.camera.forward.xyz));
#if DI_TARGET_BASE_COLOR != 0
  d.diffuse = d.g.base_color_metallic.rgb;  // Solari: base_color / PI, metallic ignored
#else
  d.diffuse = d.g.base_color_metallic.rgb * (1.0 - d.g.base_color_metallic.a);
#endif
  d.emissive = front ? d.g.emissive_roughness.rgb : vec3(0.0);
  return d;
}

// A reused sample (merge targets, the final ray, shading). DI_REUSE_RADIANCE_SCENE
// 1 (Bevy: v0.18.0:realtime/restir_di.wgsl:345, v0.19.0 :276-283): the light
// re-resolved from the scene in full precision, so the tile encoding shapes
// only the initial candidates' target and DI stays unbiased under its
// clipping or rounding; 0 (the harness's earlier model): through the encoding.
ResolvedLightSample di_resolve(LightSample s) {
#if DI_REUSE_RADIANCE_SCENE != 0
  return resolve_light_sample(s);
#else
  return resolve_light_sample_encoded(s, LIGHT_TILE_EXPOSURE, LIGHT_TILE_LOG2_RADIANCE != 0);
#endif
}

// p̂ at a surface (position, geometric and shading normal, diffuse colour).
float di_target_at(ResolvedLightSample r, vec3 position, vec3 ng, vec3 ns, vec3 diffuse) {
  LightContribution c = light_contribution(r, position, ns);
  if (dot(c.wi, ng) <= 0.0) return 0.0;
  return di_target(c, diffuse);
}

#ifdef TRACE_PREVIOUS_SCENE
// light_sample_visible (core/shared/light_sampling.h) against last frame's
// scene: whether the sample lit `position` a frame ago (Bevy #25046).
bool light_sample_visible_previous_scene(vec3 position, vec3 ng, ResolvedLightSample s) {
  vec3 spawn, dir;
  float tmax;
  return light_sample_shadow_ray(position, ng, s, spawn, dir, tmax) &&
         trace_unoccluded_previous_scene(spawn, dir, tmax);
}
#endif

bool di_dissimilar(DiPixel d, vec3 other_position, vec3 other_normal) {
  return pixel_dissimilar(d.view_z, d.position, other_position, d.ns, other_normal, DI_PLANE_TOLERANCE,
                          DI_NORMAL_MIN_DOT);
}

// The merge of reservoir o into canonical c at this pixel. DI_MIS_VISIBILITY:
// the caller has put visibility into t.po_xc and t.pc_xo (Bevy main), and the
// spatial merge (defensive) mixes in c's confidence share; otherwise the
// profile's balance or constant weights.
MergeResult di_merge(DiReservoir c, DiReservoir o, MergeTargets t, bool spatial, float u) {
#if DI_MIS_VISIBILITY != 0
  return merge_di_reservoirs_defensive(c, o, t, spatial, u);
#else
  return merge_di_reservoirs(c, o, t, DI_BALANCE_MIS != 0, u);
#endif
}
