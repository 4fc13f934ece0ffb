// What the ReSTIR GI and specular GI passes share (docs/design.md §3 steps 7-8):
// bindings, the pixel's surface from the G-buffer, the cache query of a GI
// sample's hit (its radiance: hit_radiance.glsl), and the merge with its statistics. Include after
// scene_bindings.glsl (with the path integrator).
//
// Defines (gpu/passes/restir_gi_settings.cpp): GI_CONFIDENCE_CAP,
// GI_SPATIAL_RADIUS, GI_SPATIAL_TRIES, GI_CONSISTENT_MIS (restir_gi.mis_weights), GI_PLANE_TOLERANCE, GI_NORMAL_MIN_DOT,
// GI_JACOBIAN_REJECT (threshold), GI_JACOBIAN_REJECTION (1: reject above it),
// GI_JACOBIAN_BOTH (1: in both directions, Solari 0.19),
// GI_TEMPORAL_PERMUTATION (1: permutation sampling), GI_TEMPORAL_FALLBACK (0
// none, 1 point reprojection, 2 up to 4 permutations), GI_TARGET_BRDF,
// GI_EMPTY_NO_CONFIDENCE, GI_EMISSIVE_TEST, GI_VISIBILITY_FINAL,
// GI_SHADING_DIFFUSE, GI_SKIP_SMOOTH_METALS, GI_SECONDARY_ALBEDO_BASE (GiSettings says what each
// selects), GI_HIT_RADIANCE (0: one
// NEE light sample, 1: one cosine-sampled path, 2: the world cache, with the
// cache's WORLD_CACHE_* defines), GI_SECONDARY_HITS_FULL (brdf.secondary_hits), GI_RAY_TMAX,
// SPECULAR_REUSE_ROUGHNESS, SPECULAR_MAX_BOUNCES, SPECULAR_MIN_PERCEPTUAL_ROUGHNESS.
#include "core/shared/restir_gi.h"
#include "core/shared/restir_di.h"
#include "core/shared/specular.h"
#include "gpu/shaders/gbuffer.h"
#include "gpu/shaders/gi_bindings.h"

layout(push_constant) uniform Push { GiPushConstants push; };

#ifndef GI_JACOBIAN_BOTH
#define GI_JACOBIAN_BOTH 0
#endif

#if GI_HIT_RADIANCE == 2
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/world_cache_query.glsl"
#endif

layout(std430, set = 0, binding = BINDING_GBUFFER) readonly buffer GBuffer { GBufferTexel gbuffer[]; };
layout(std430, set = 0, binding = BINDING_GI_STATS) buffer Stats { GiStats gi_stats; };
#if GI_PATH_COUNTERS != 0
layout(std430, set = 0, binding = BINDING_GI_COUNTERS) buffer Counters { GiCounters gi_counters; };
#endif

vec3 gi_target_colour(vec3 base_color);

struct GiPixel {
  bool hit;
  vec3 position;
  vec3 ng;       // geometric normal on the camera's side
  vec3 ns;       // shading normal on that side
  vec3 view;     // unit, towards the camera
  float view_z;
  vec3 base_color;
  float metallic;
  float perceptual_roughness;
  float reflectance;
  vec3 diffuse;  // base colour · (1 − metallic)
  BrdfParams brdf;  // the surface under its material model (brdf.h)
  vec3 target;   // the resampling target's colour at this surface (gi_target_colour)
  vec4 motion;   // xy pixels to the previous frame, z 1 if valid
};

GiPixel gi_pixel(uvec2 pixel) {
  uvec2 resolution = frame.resolution_frame.xy;
  GBufferTexel g = gbuffer[pixel.y * resolution.x + pixel.x];
  GiPixel d;
  d.hit = g.geometric_normal.w > 0.0;
  vec3 dir = camera_ray_direction(frame.camera, pixel, resolution);
  d.position = g.position_depth.xyz;
  d.ng = dot(dir, g.geometric_normal.xyz) < 0.0 ? g.geometric_normal.xyz : -g.geometric_normal.xyz;
  d.ns = dot(g.shading_normal.xyz, d.ng) < 0.0 ? -g.shading_normal.xyz : g.shading_normal.xyz;
  d.view = -dir;
  d.view_z = dot(d.position - frame.camera.position.xyz, normalize(frame.camera.forward.xyz));
  d.base_color = g.base_color_metallic.rgb;
  d.metallic = g.base_color_metallic.a;
  d.perceptual_roughness = g.emissive_roughness.a;
  d.reflectance = g.motion_reflectance.w;
  d.diffuse = d.base_color * (1.0 - d.metallic);
  d.brdf = brdf_params(d.base_color, d.metallic, d.perceptual_roughness, d.reflectance, gbuffer_brdf_model(g));
  d.target = gi_target_colour(d.base_color);
  d.motion = vec4(g.motion_reflectance.xyz, 0.0);
  return d;
}

// Whether ReSTIR GI leaves this pixel out (GI_SKIP_SMOOTH_METALS, Solari
// 0.19: a smooth metal, v0.19.0:realtime/restir_gi.wgsl:33-36,59-62, with
// Bevy's alpha = perceptual roughness², unclamped, against 0.4): its
// reservoirs are empty and it shades no GI.
bool gi_skips_pixel(GiPixel d) {
#if GI_SKIP_SMOOTH_METALS != 0
  return d.metallic > 0.9999 && d.perceptual_roughness * d.perceptual_roughness <= float(SPECULAR_REUSE_ROUGHNESS);
#else
  return false;
#endif
}

bool gi_dissimilar(GiPixel d, vec3 other_position, vec3 other_normal) {
  return pixel_dissimilar(d.view_z, d.position, other_position, d.ns, other_normal, GI_PLANE_TOLERANCE,
                          GI_NORMAL_MIN_DOT);
}

// An edge pixel: one of its four neighbours this frame is a miss or a surface
// reuse would refuse as dissimilar (the test above). Where the temporal_acceptance
// check counts reuse (GI_TEMPORAL_EDGE_STATS).
bool gi_pixel_at_edge(GiPixel d, uvec2 pixel) {
  const ivec2 size = ivec2(frame.resolution_frame.xy);
  const ivec2 steps[4] = ivec2[](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
  for (int i = 0; i < 4; ++i) {
    ivec2 p = ivec2(pixel) + steps[i];
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) continue;
    GiPixel o = gi_pixel(uvec2(p));
    if (!o.hit || gi_dissimilar(d, o.position, o.ns)) return true;
  }
  return false;
}

// The query ids of the GI passes' pixel-rooted cache queries: after the cache
// view's (the pixel indices), the initial samples' per chain, then specular
// GI's per chain; unique within the pending list they share (lowest id wins a slot).
uint gi_cache_query_id(uint pass_block, uint chain, uint index) {
  uint pixels = frame.resolution_frame.x * frame.resolution_frame.y;
  return (1u + pass_block * push.chain_count + chain) * pixels + index;
}

// The colour the resampling target weighs a sample's radiance with at a
// surface: Solari's base colour / π, metallic ignored (GI_TARGET_BRDF 1:
// v0.18.0 realtime/restir_gi.wgsl:46,68,262-271, v0.17.0 :262-276), or 1
// (0: luminance(L)·cos, the harness's earlier target).
vec3 gi_target_colour(vec3 base_color) {
#if GI_TARGET_BRDF != 0
  return base_color * INV_PI;
#else
  return vec3(1.0);
#endif
}

// The normal a GI sample keeps for the reuse jacobian (restir_gi.sample_normal):
// Solari's sample_point.world_normal, the hit's shading normal unflipped
// (v0.18.0 realtime/restir_gi.wgsl:108), whose jacobian is 0 from a back face
// (:206-209 saturate both cosines); or ng, the face normal facing the ray.
vec3 gi_sample_normal(SurfacePoint s, vec3 ng) {
#if GI_SAMPLE_NORMAL_SHADING != 0
  return s.shading_normal;
#else
  return ng;
#endif
}

// Secondary hits (hit_radiance.glsl) with this pass's settings.
#define HIT_RADIANCE GI_HIT_RADIANCE
#define HIT_SURFACES_FULL GI_SECONDARY_HITS_FULL
#define HIT_GLOSSY_ROUGHNESS SPECULAR_REUSE_ROUGHNESS
#define HIT_GLOSSY_BOUNCES SPECULAR_MAX_BOUNCES
#define HIT_ALBEDO_BASE GI_SECONDARY_ALBEDO_BASE
#define HIT_POWER_MIS SPECULAR_POWER_MIS
#define HIT_RUSSIAN_ROULETTE SPECULAR_RUSSIAN_ROULETTE
#define HIT_MIS_LIGHT_PDF_AREA SPECULAR_MIS_LIGHT_PDF_AREA
#define HIT_MESH_TANGENT_FRAME SPECULAR_MESH_TANGENT_FRAME
#define HIT_PERFECT_MIRROR_METAL SPECULAR_PERFECT_MIRROR_METAL
#define HIT_SUN_NEE_ONLY SPECULAR_SUN_NEE_ONLY
#define HIT_CACHE_NORMAL_VERTEX GI_HIT_CACHE_NORMAL_VERTEX
#include "gpu/shaders/hit_radiance.glsl"

// A GI pass's pixel-rooted cache query (GI_HIT_RADIANCE 2): full lifetime,
// root frame = this frame, the id from gi_cache_query_id, the pending list the
// cache view shares; an empty cell is claimed and committed after the GI
// passes (WorldCache::record_commit). first_bounce: ReSTIR GI's initial
// sample (0.19's light-leak rule, WORLD_CACHE_LEAK_RULE), not specular GI's path.
CacheQuery gi_pixel_query(uint query_id, bool first_bounce) {
  CacheQuery q;
#if GI_HIT_RADIANCE == 2
  q.life = uint(WORLD_CACHE_LIFETIME);
#else
  q.life = 0u;
#endif
  q.root_frame = frame.resolution_frame.z;
  q.id = query_id;
  q.list = 1u;
  q.first_bounce = first_bounce ? 1u : 0u;
  return q;
}

// Whether point `target` is visible from surface point p (geometric normal ng).
bool gi_point_visible(vec3 p, vec3 ng, vec3 target) {
  vec3 spawn = offset_ray_origin(p, ng);
  vec3 to_target = target - spawn;
  float dist = length(to_target);
  return dist > 0.0 && dot(to_target, ng) > 0.0 && trace_unoccluded(spawn, to_target / dist, dist * (1.0 - 1e-3));
}

// Pairwise merge of the canonical reservoir c (surface pc, nc, target colour
// tc) with o, found at another surface (po, no, to); jacobian rejection and
// statistics here.
// c_visible_at_o: whether c's sample point is visible from o. The balance
// heuristic needs p_o(x_c) with o's visibility, else c's sample keeps only
// its share where o could not have produced it and GI comes out dark — the
// mechanism of the DI bias (README), here for GI's spatial reuse.
GiReservoir gi_merge(GiReservoir c, vec3 pc, vec3 nc, vec3 tc, GiReservoir o, vec3 po, vec3 no, vec3 to,
                     bool c_visible_at_o, float u) {
  bool o_valid = gi_reservoir_valid(o);
  bool c_valid = gi_reservoir_valid(c);
  GiMergeInputs t;
  t.j_co = 0.0;
  t.j_oc = c_valid ? gi_jacobian(po, pc, c.sample_position.xyz, c.sample_normal.xyz) : 0.0;
  if (o_valid) {
    atomicAdd(gi_stats.merges, 1u);
    float raw = gi_jacobian_raw(pc, po, o.sample_position.xyz, o.sample_normal.xyz);
    if (!gi_finite(raw)) atomicAdd(gi_stats.nonfinite_jacobians, 1u);
    t.j_co = gi_finite(raw) ? raw : 0.0;
#if GI_JACOBIAN_REJECTION != 0
    // GI_JACOBIAN_BOTH bounds the factor a sample's weight picks up per hop
    // from below too. Solari 0.19 (v0.19.0 realtime/restir_gi.wgsl:276, Bevy
    // #23968) refuses the pair when either sample's move has J above the
    // threshold; the consistent weights use the per-sample form of that rule,
    // J_co(x_o) in [1/threshold, threshold] (and the same for x_c below), so
    // which shifts are allowed does not depend on the other pixel's sample.
#if GI_JACOBIAN_BOTH != 0 && GI_CONSISTENT_MIS != 0
    bool refuse = t.j_co > float(GI_JACOBIAN_REJECT) || t.j_co * float(GI_JACOBIAN_REJECT) < 1.0;
#elif GI_JACOBIAN_BOTH != 0
    bool refuse = t.j_co > float(GI_JACOBIAN_REJECT) || t.j_oc > float(GI_JACOBIAN_REJECT);
#else
    bool refuse = t.j_co > float(GI_JACOBIAN_REJECT);
#endif
    if (refuse) {
      atomicAdd(gi_stats.rejections, 1u);
#if GI_CONSISTENT_MIS != 0
      // Its sample is refused, its confidence still counts: the canonical
      // sample's weight must be the same whatever o drew.
      o.radiance.w = 0.0;
      o_valid = false;
#else
      return c;  // Solari: the neighbour is skipped
#endif
    }
#endif
    if (o_valid) {
      atomicMax(gi_stats.max_accepted_j_bits, floatBitsToUint(t.j_co));
      atomicAdd(gi_stats.histogram[gi_jacobian_bin(t.j_co)], 1u);
    }
  }
  t.pc_xc = c_valid ? gi_target(c.radiance.rgb * tc, c.sample_position.xyz, pc, nc) : 0.0;
  t.po_xc = c_valid && c_visible_at_o ? gi_target(c.radiance.rgb * to, c.sample_position.xyz, po, no) : 0.0;
#if GI_CONSISTENT_MIS != 0 && GI_JACOBIAN_REJECTION != 0
  // o could have produced c's sample only through a shift of jacobian
  // 1/J_oc, refused above the threshold (and, GI_JACOBIAN_BOTH, below its
  // inverse): then it has no share of it.
  if (!(t.j_oc * float(GI_JACOBIAN_REJECT) >= 1.0)) t.po_xc = 0.0;
#if GI_JACOBIAN_BOTH != 0
  if (t.j_oc > float(GI_JACOBIAN_REJECT)) t.po_xc = 0.0;
#endif
#endif
  t.po_xo = o_valid ? gi_target(o.radiance.rgb * to, o.sample_position.xyz, po, no) : 0.0;
  t.pc_xo = o_valid ? gi_target(o.radiance.rgb * tc, o.sample_position.xyz, pc, nc) : 0.0;
  return merge_gi_reservoirs(c, o, t, u).merged;
}
