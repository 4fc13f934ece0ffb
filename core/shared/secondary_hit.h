// The radiance a secondary hit sends back along the ray that found it, without
// the hit's own emission (DI owns a pixel's direct light; the cache's direct
// sample owns a cell's). One file for every secondary hit: ReSTIR GI's initial
// sample, specular GI's glossy path and the world cache's own GI ray on the
// GPU (gpu/shaders/hit_radiance.glsl), and the CPU tests that hold it to the
// reference path tracer (tests/secondary_hit_test.cpp).
//
// Bridge-included after path_integrator.h (see scene_access.h); include
// specular.h first, at file scope. The includer defines:
//   HIT_RADIANCE          how a path ends at a hit treated as diffuse: 0 one
//                         light sample (Bevy's NO_WORLD_CACHE), 1 one
//                         cosine-sampled path traced on, 2 the world cache
//   HIT_SURFACES_FULL     brdf.secondary_hits: 0 "diffuse" (Solari 0.18: "as
//                         far as the world cache is concerned, all surfaces are
//                         diffuse only"), 1 "full" (see secondary_hit_radiance)
//   HIT_GLOSSY_ROUGHNESS  alpha at or below which a hit is followed along its
//                         BRDF (specular.reuse_gi_roughness)
//   HIT_GLOSSY_BOUNCES    vertices a glossy path visits (specular.max_bounces)
//   HIT_POWER_MIS         specular.mis: 1 "power" (Solari 0.18's glossy path),
//                         0 "balance" heuristic between NEE and the bounce
//   HIT_MESH_TANGENT_FRAME brdf.sampling_frame: 1 "mikktspace" (Solari 0.18:
//                         a hit with a mesh tangent bounces in the skewed
//                         frame, sample_specular_in_mesh_frame), 0 "orthonormal"
//   HIT_MIS_LIGHT_PDF_AREA specular.mis_light_pdf: 1 "area" (every release:
//                         the light's pdf weighed in area measure against
//                         the bounce's in solid angle), 0 "solid_angle" (#24671)
//   HIT_RUSSIAN_ROULETTE  specular.russian_roulette: 1 ends a glossy path
//                         after a bounce with probability 1 − luminance of
//                         its throughput (Solari 0.19), 0 never
//   HIT_PERFECT_MIRROR_METAL specular.perfect_mirror: 1 "alpha_and_metallic"
//                         (Solari 0.18 and 0.19: a vertex skips NEE, and the
//                         emitter its bounce hits gets weight 1, only at alpha
//                         <= 0.001 and metallic > 0.9999: v0.18.0
//                         realtime/specular_gi.wgsl:109), 0 "alpha" (alpha alone)
//   HIT_MIRROR_THROUGHPUT_BRDF specular.mirror_throughput: 1 "full_brdf"
//                         (Solari 0.19, its specular GI pass only: at a vertex
//                         of alpha <= 0.001 the bounce is the exact
//                         reflection and the throughput is multiplied by the
//                         whole BRDF·cos there, with no pdf, so a smooth
//                         dielectric adds its diffuse lobe to the mirror
//                         weight; NEE there has weight 1, since the bounce
//                         never samples that lobe: v0.19.0
//                         realtime/specular_gi.wgsl:155-159, :196-197),
//                         0 "sampled" (the sampled lobe mixture's f·cos/pdf)
//   HIT_SUN_NEE_ONLY      specular.directional_lights: 1 "nee_only" (Solari: a
//                         directional light's NEE sample has weight 1, since
//                         no BRDF ray can hit it, and a bounce that escapes
//                         adds nothing: v0.18.0 realtime/specular_gi.wgsl:93,
//                         159-161), 0 "mis" (NEE weighed against the bounce,
//                         an escaped bounce adding the sun at the balance weight)
//   HIT_ALBEDO_BASE       brdf.secondary_albedo: 1 "base_color" (Solari: the
//                         full base colour, metals too: v0.18.0
//                         realtime/restir_gi.wgsl:120, world_cache_update.wgsl:43,
//                         specular_gi.wgsl:116), 0 "diffuse" base·(1 − metallic)
//   HIT_CACHE_NORMAL_VERTEX world_cache.hit_normal: 1 "vertex" (Solari: a
//                         hit queries the cache with its interpolated vertex
//                         normal, never flipped, so a back face keys its
//                         front's cell: v0.18.0 realtime/restir_gi.wgsl:116,
//                         specular_gi.wgsl:117, world_cache_update.wgsl:43),
//                         0 "face_toward_ray" (the face normal facing the ray)
// and, for HIT_RADIANCE 2, the cache it ends in:
//   vec3  hit_cache_irradiance(vec3 position, vec3 ng, float ray_t, CacheQuery q, INOUT(uint) rng);
//   float hit_cache_cell_size(vec3 position, uint rng);   // the cell's edge there
//                                              // (rng: a copy, for 0.19's stochastic LOD)
// No include guard on purpose (C++ includes it into each bridge struct).

// Where a path ending in the world cache queries it: the life and root frame
// the query passes on, its id in the pending list, which list, and whether it
// is ReSTIR GI's first bounce (0.19's light-leak rule applies there only)
// (world_cache_query's parameters; unused for HIT_RADIANCE 0 and 1).
struct CacheQuery {
  uint life;
  uint root_frame;
  uint id;
  uint list;
  uint first_bounce;
};

#if HIT_RADIANCE == 2 && !defined(__cplusplus)
vec3 hit_cache_irradiance(vec3 position, vec3 ng, float ray_t, CacheQuery q, inout uint rng);
float hit_cache_cell_size(vec3 position, uint rng);
#endif
#ifndef HIT_RUSSIAN_ROULETTE
#define HIT_RUSSIAN_ROULETTE 0
#endif
#ifndef HIT_MIS_LIGHT_PDF_AREA
#define HIT_MIS_LIGHT_PDF_AREA 0
#endif
#ifndef HIT_MESH_TANGENT_FRAME
#define HIT_MESH_TANGENT_FRAME 0
#endif
#ifndef HIT_PERFECT_MIRROR_METAL
#define HIT_PERFECT_MIRROR_METAL 0
#endif
#ifndef HIT_SUN_NEE_ONLY
#define HIT_SUN_NEE_ONLY 0
#endif
#ifndef HIT_MIRROR_THROUGHPUT_BRDF
#define HIT_MIRROR_THROUGHPUT_BRDF 0
#endif
#ifndef HIT_CACHE_NORMAL_VERTEX
#define HIT_CACHE_NORMAL_VERTEX 0
#endif

// The normal a hit queries the world cache with (HIT_CACHE_NORMAL_VERTEX);
// ng is the face normal facing the ray.
GI_FN vec3 hit_cache_normal(SurfacePoint s, vec3 ng) {
#if HIT_CACHE_NORMAL_VERTEX != 0
  return s.vertex_normal;
#else
  return ng;
#endif
}

GI_FN uint hit_mis_heuristic() {
  return (HIT_POWER_MIS != 0 ? MIS_POWER : MIS_BALANCE) | (HIT_MIS_LIGHT_PDF_AREA != 0 ? MIS_LIGHT_PDF_AREA : 0u) |
         (HIT_SUN_NEE_ONLY != 0 ? MIS_DIRECTIONAL_UNWEIGHTED : 0u);
}

// A path ends here: the hit's diffuse lobe times the irradiance arriving there
// (radiance = irradiance · diffuse / π, as Solari's world cache). With
// HIT_SURFACES_FULL the specular lobe adds its directional albedo to the
// diffuse colour: a rough lobe (alpha above HIT_GLOSSY_ROUGHNESS) spreads the
// irradiance nearly as a diffuse one does, the approximation specular GI makes
// when it reuses the GI sample on rough pixels. The albedo is estimated with
// one bounded-VNDF sample's weight F·G2/G1 (unbiased, no ray traced;
// Karis's analytic fit was up to 0.2 off this BRDF). ng faces the ray, v
// towards where it came from, ray_t the length of the ray that found s.
GI_FN vec3 end_path_radiance(SurfacePoint s, vec3 ng, vec3 ns, vec3 v, float ray_t, CacheQuery q,
                             INOUT(uint) rng) {
#if HIT_ALBEDO_BASE != 0 && HIT_SURFACES_FULL == 0
  // ("full" models the lobes itself: the diffuse colour plus the specular albedo.)
  vec3 albedo = vec3(s.base_color_metallic);
#else
  vec3 albedo = vec3(s.base_color_metallic) * (1.0f - s.base_color_metallic.w);
#endif
#if HIT_SURFACES_FULL != 0
  BrdfParams brdf = surface_brdf(s);
  if (brdf_has_specular(brdf) && dot(ns, v) > 0.0f) {
    vec3 l = to_world(sample_ggx_bounded_vndf(from_world(v, ns), brdf.alpha, rng_next_vec2(rng)), ns);
    if (dot(l, ns) > 0.0f) albedo += specular_sample_weight(brdf, ns, v, l);
  }
#endif
#if HIT_RADIANCE == 2
  // Solari's query_world_cache at the hit. Queried even on a black surface,
  // as Solari does, so the cell exists.
  return albedo * INV_PI * hit_cache_irradiance(s.position, hit_cache_normal(s, ng), ray_t, q, rng);
#else
  if (max3(albedo) <= 0.0f) return vec3(0.0f);
  vec3 spawn = offset_ray_origin(s.position, ng);
#if HIT_RADIANCE == 0
  // One light sample on the diffuse lobe alone, unweighted (Bevy's
  // NO_WORLD_CACHE path: nothing else at this hit sees the lights).
  vec3 l;
  float dist;
  vec3 le;
  float pdf;
  float area_pdf;
  if (!sample_light(s.position, rng, l, dist, le, pdf, area_pdf) || dot(l, ng) <= 0.0f) return vec3(0.0f);
  if (!light_sample_visible(s.position, spawn, l, dist)) return vec3(0.0f);
  return albedo * INV_PI * le * max(dot(ns, l), 0.0f) / pdf;
#else
  // albedo · L_in: the cosine-sampled pdf cancels cos/π.
  vec3 l = to_world(sample_cosine_hemisphere(rng_next_vec2(rng)), ns);
  if (dot(l, ng) <= 0.0f) return vec3(0.0f);
  return albedo * path_trace(spawn, l, rng, 32u);
#endif
#endif
}

// Where a glossy path ends in end_path_radiance (the cache).
// - spread_a0 < 0: at the first hit rougher than HIT_GLOSSY_ROUGHNESS (the
//   harness's earlier rule, and brdf.secondary_hits full's).
// - spread_a0 ≥ 0 (specular.path_end "path_spread", Solari 0.18: v0.18.0
//   realtime/specular_gi.wgsl:58-61,111-118, after Müller et al. 2021 §3.4):
//   when the path's footprint, spread += sqrt(t² / (pdf · cos θ_o)) at each
//   hit, satisfies spread² > a0 · the cache's cell size there, a0 =
//   0.03 · |camera − primary|² / (4π cos θ) (specular_gi.comp). A mirror
//   bounce (pdf a delta) adds no spread. Needs the cache (HIT_RADIANCE 2).
// - path_roughness ≥ 0 (specular.path_end "long_ray_rough_path", Solari
//   0.19: v0.19.0 realtime/specular_gi.wgsl:131-139): at the third vertex,
//   or where the ray that reached the hit is longer than √3 cells and the
//   path's summed alpha (the primary's plus each vertex's passed) exceeds
//   HIT_GLOSSY_ROUGHNESS. The cell size is drawn from a copy of the stream,
//   as Bevy's. Takes precedence over spread_a0.
struct GlossyPathEnd {
  float spread_a0;
  float path_roughness;
  float first_pdf;  // solid-angle pdf of the primary direction (≥ 1e30: a mirror)
  // 1: count the first hit's emission with weight 1 (DI handed this surface's
  // specular lobe over, specular.di_handover_alpha); 0: DI owns it.
  float first_emission;
};

GI_FN GlossyPathEnd glossy_path_end(float spread_a0, float first_pdf, float first_emission) {
  GlossyPathEnd e;
  e.spread_a0 = spread_a0;
  e.path_roughness = -1.0f;
  e.first_pdf = first_pdf;
  e.first_emission = first_emission;
  return e;
}

// The path from a hit onwards (trace_glossy_path of seeds/solari-0.18.md, from
// its first hit): a rough hit ends it in end_path_radiance; a glossy one gets
// NEE (not on mirrors) and a BRDF-sampled bounce, emission found by the
// bounce weighted against NEE (hit_mis_heuristic), for at most
// HIT_GLOSSY_BOUNCES vertices. At the last vertex Solari stops after NEE
// (light beyond it is lost); HIT_SURFACES_FULL ends the path there in
// end_path_radiance instead.
//
// trace_first: the path starts with a trace from `spawn` along `dir` (a miss
// returns black: escaped light at the first vertex is DI's); otherwise at
// `hit`. Every segment is traced by the one call at the top of the loop: the
// shader compiler inlines the whole traversal at each call.
GI_FN vec3 glossy_path_radiance_from(bool trace_first, Hit hit, vec3 spawn, vec3 dir, CacheQuery q,
                                     GlossyPathEnd path_end, INOUT(uint) rng) {
  vec3 radiance = vec3(0.0f);
  vec3 throughput = vec3(1.0f);
  float previous_pdf = 0.0f;  // of the direction just traced; 0: no NEE at its origin (mirror or first vertex)
#if HIT_RADIANCE == 2
  float spread = 0.0f;
  float spread_pdf = path_end.first_pdf;
#endif
  for (uint vertex = 0u;; ++vertex) {
    if (vertex > 0u || trace_first) {
#ifdef GLOSSY_SEGMENT_TRACED
      GLOSSY_SEGMENT_TRACED();  // the includer's ray count (specular_gi.comp, GI_PATH_COUNTERS)
#endif
      if (!trace_closest(spawn, dir, RAY_TMAX, hit)) {
        if (vertex > 0u && HIT_SUN_NEE_ONLY == 0) radiance += throughput * escaped_radiance(dir, previous_pdf);
        break;
      }
    }
    SurfacePoint s = surface_at_hit(hit);
    bool front = dot(dir, s.geometric_normal) < 0.0f;
    if (vertex == 0u && front) radiance += path_end.first_emission * s.emissive;
    if (vertex > 0u && front && max3(s.emissive) > 0.0f) {
      float light_pdf = emissive_hit_light_pdf(s, hit.instance, dir, hit.t);
#if HIT_MIS_LIGHT_PDF_AREA != 0
      light_pdf *= -dot(dir, s.geometric_normal) / (hit.t * hit.t);  // solid angle → area at the light
#endif
      float w = previous_pdf > 0.0f ? mis_weight(hit_mis_heuristic(), previous_pdf, light_pdf) : 1.0f;
      radiance += throughput * s.emissive * w;
    }
    vec3 hng = front ? s.geometric_normal : -s.geometric_normal;
    vec3 hns = dot(s.shading_normal, hng) < 0.0f ? -s.shading_normal : s.shading_normal;
    vec3 v = -dir;
    BrdfParams brdf = surface_brdf(s);
    bool last = vertex + 1u >= uint(HIT_GLOSSY_BOUNCES);
    // HIT_SURFACES_FULL ends the path at its last vertex in the cache, which
    // holds that vertex's direct light too: no NEE there.
    bool end_here = brdf.alpha > float(HIT_GLOSSY_ROUGHNESS) || (HIT_SURFACES_FULL != 0 && last);
#if HIT_RADIANCE == 2
    if (path_end.path_roughness >= 0.0f) {
      bool long_ray = hit.t > sqrt(3.0f) * hit_cache_cell_size(s.position, rng);
      end_here = last || (long_ray && path_end.path_roughness > float(HIT_GLOSSY_ROUGHNESS));
    } else if (path_end.spread_a0 >= 0.0f) {
      spread += sqrt(hit.t * hit.t / (spread_pdf * max(dot(hns, v), 1e-6f)));
      end_here = spread * spread > path_end.spread_a0 * hit_cache_cell_size(s.position, rng);
    }
#endif
    if (end_here) {
      radiance += throughput * end_path_radiance(s, hng, hns, v, hit.t, q, rng);
      break;
    }
    spawn = offset_ray_origin(s.position, hng);
    bool delta_lobe = brdf.alpha <= SPECULAR_MIRROR_ALPHA;
    bool mirror = delta_lobe && (HIT_PERFECT_MIRROR_METAL == 0 || s.base_color_metallic.w > 0.9999f);
#if HIT_MIRROR_THROUGHPUT_BRDF != 0
    // Solari 0.19: the bounce at alpha <= 0.001 is the reflection alone (its
    // pdf infinite), so NEE there takes weight 1 (nee_mis_weight's p_bounce 0).
    uint nee_heuristic = delta_lobe ? MIS_NONE : hit_mis_heuristic();
#else
    uint nee_heuristic = hit_mis_heuristic();
#endif
    if (!mirror) add_next_event(brdf, s.position, hng, hns, v, spawn, throughput, nee_heuristic, radiance, rng);
    if (last) break;  // Solari: light beyond the last vertex is lost
    vec3 u = vec3(rng_next_float(rng), rng_next_float(rng), rng_next_float(rng));
    vec3 l;
    float pdf;
#if HIT_MIRROR_THROUGHPUT_BRDF != 0
    if (delta_lobe) {
      // Solari 0.19 (v0.19.0 realtime/specular_gi.wgsl:156-159): throughput
      // *= evaluate_brdf, diffuse lobe included, and no division by the pdf:
      // a smooth dielectric reflects F + diffuse·layering·cos instead of F.
      l = reflect(-v, hns);
      if (dot(l, hng) <= 0.0f) break;
      throughput *= specular_sample_weight(brdf, hns, v, l) + brdf_eval_diffuse(brdf, hns, v, l) * max(dot(hns, l), 0.0f);
      pdf = 0.0f;  // the emission the reflection finds: weight 1 (power_heuristic(INF, p_light))
    } else
#endif
#if HIT_MESH_TANGENT_FRAME != 0
    if (s.mesh_tangent.w != 0.0f) {
      // Solari 0.18: GGX alone in the mesh's frame, the BRDF at the unnormalised sample.
      if (!sample_specular_in_mesh_frame(brdf, hns, s.mesh_tangent, v, vec2(u.x, u.y), l, pdf)) break;
      throughput *= brdf_eval(brdf, hns, v, l) * (max(dot(hns, l), 0.0f) / pdf);
      l = normalize(l);
      if (dot(l, hng) <= 0.0f) break;
    } else
#endif
    {
      if (!brdf_sample(brdf, hns, v, u, l, pdf) || dot(l, hng) <= 0.0f) break;
      throughput *= brdf_eval(brdf, hns, v, l) * (max(dot(hns, l), 0.0f) / pdf);
    }
    previous_pdf = mirror ? 0.0f : pdf;
#if HIT_RADIANCE == 2
    spread_pdf = delta_lobe ? 1e30f : pdf;
    if (path_end.path_roughness >= 0.0f) path_end.path_roughness += brdf.alpha;
#endif
#if HIT_RUSSIAN_ROULETTE != 0
    // Solari 0.19's roulette (v0.19.0 realtime/specular_gi.wgsl:162-165),
    // with its quirk: a throughput of luminance above 1 is divided by it.
    // (p = 0 ends the path here, where Bevy's rand_f = 0 would divide by 0.)
    float p_continue = luminance(throughput);
    if (p_continue <= 0.0f || rng_next_float(rng) > p_continue) break;
    throughput /= p_continue;
#endif
    dir = l;
    q.first_bounce = 0u;  // a later vertex is not GI's first bounce
  }
  return radiance;
}

GI_FN vec3 glossy_path_radiance(Hit hit, vec3 dir, CacheQuery q, GlossyPathEnd path_end, INOUT(uint) rng) {
  return glossy_path_radiance_from(false, hit, vec3(0.0f), dir, q, path_end, rng);
}

// What a GI sample (or a cache cell's GI ray) receives from its hit: Solari
// ("diffuse") ends the path at once; "full" follows a glossy hit along its
// BRDF first, so light that reaches a diffuse surface by way of a mirror or
// glossy metal is not lost.
GI_FN vec3 secondary_hit_radiance(Hit hit, SurfacePoint s, vec3 ng, vec3 ns, vec3 dir, CacheQuery q,
                                  INOUT(uint) rng) {
#if HIT_SURFACES_FULL != 0
  return glossy_path_radiance(hit, dir, q, glossy_path_end(-1.0f, 0.0f, 0.0f), rng);
#else
  return end_path_radiance(s, ng, ns, -dir, hit.t, q, rng);
#endif
}
