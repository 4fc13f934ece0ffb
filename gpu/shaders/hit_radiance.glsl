// The radiance a secondary hit sends back along the ray that found it, without
// the hit's own emission (DI owns a pixel's direct light; the cache's direct
// sample owns a cell's). One file for every secondary hit: ReSTIR GI's initial
// sample, specular GI's glossy path, and the world cache's own GI ray.
//
// Include after scene_bindings.glsl with the path integrator (and, for
// HIT_RADIANCE 2, world_cache_common.glsl and world_cache_query.glsl). The
// includer defines:
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
//   HIT_ALBEDO_BASE       brdf.secondary_albedo: 1 "base_color" (Solari: the
//                         full base colour, metals too: v0.18.0
//                         realtime/restir_gi.wgsl:120, world_cache_update.wgsl:43,
//                         specular_gi.wgsl:116), 0 "diffuse" base·(1 − metallic)

#include "core/shared/specular.h"

float hit_mis(float a, float b) {
#if HIT_POWER_MIS != 0
  return power_heuristic(a, b);
#else
  return balance_heuristic(a, b);
#endif
}

// Where a path ending in the world cache queries it: the life and root frame
// the query passes on, its id in the pending list, and which list
// (world_cache_query's parameters; unused for HIT_RADIANCE 0 and 1).
struct CacheQuery {
  uint life;
  uint root_frame;
  uint id;
  uint list;
};

// A path ends here: the hit's diffuse lobe times the irradiance arriving there
// (radiance = irradiance · diffuse / π, as Solari's world cache). With
// HIT_SURFACES_FULL the specular lobe adds its directional albedo to the
// diffuse colour: a rough lobe (alpha above HIT_GLOSSY_ROUGHNESS) spreads the
// irradiance nearly as a diffuse one does, the approximation specular GI makes
// when it reuses the GI sample on rough pixels. The albedo is estimated with
// one bounded-VNDF sample's weight F·G2/G1 (unbiased, no ray traced;
// Karis's analytic fit was up to 0.2 off this BRDF). ng faces the ray, v
// towards where it came from.
vec3 end_path_radiance(SurfacePoint s, vec3 ng, vec3 ns, vec3 v, CacheQuery q, inout uint rng) {
  GpuMaterial m = scene_material(s.material);
#if HIT_ALBEDO_BASE != 0 && HIT_SURFACES_FULL == 0
  // ("full" models the lobes itself: the diffuse colour plus the specular albedo.)
  vec3 albedo = vec3(m.base_color_metallic);
#else
  vec3 albedo = vec3(m.base_color_metallic) * (1.0 - m.base_color_metallic.w);
#endif
#if HIT_SURFACES_FULL != 0
  BrdfParams brdf = material_brdf(s.material);
  if (max3(brdf.f0) > 0.0 && dot(ns, v) > 0.0) {
    vec3 l = to_world(sample_ggx_bounded_vndf(from_world(v, ns), brdf.alpha, rng_next_vec2(rng)), ns);
    if (dot(l, ns) > 0.0) albedo += specular_sample_weight(brdf.f0, brdf.alpha, ns, v, l);
  }
#endif
#if HIT_RADIANCE == 2
  // Solari's query_world_cache at the hit. Queried even on a black surface,
  // as Solari does, so the cell exists.
  vec3 irradiance = world_cache_query(s.position, ng, q.life, q.root_frame, q.id, q.list);
  return albedo * INV_PI * irradiance;
#else
  if (max3(albedo) <= 0.0) return vec3(0.0);
  vec3 spawn = offset_ray_origin(s.position, ng);
#endif
#if HIT_RADIANCE == 0
  vec3 l;
  float dist;
  vec3 le;
  float pdf;
  if (!sample_light(s.position, rng, l, dist, le, pdf) || dot(l, ng) <= 0.0) return vec3(0.0);
  if (!light_sample_visible(s.position, spawn, l, dist)) return vec3(0.0);
  return albedo * INV_PI * le * max(dot(ns, l), 0.0) / pdf;
#elif HIT_RADIANCE == 1
  // albedo · L_in: the cosine-sampled pdf cancels cos/π.
  vec3 l = to_world(sample_cosine_hemisphere(rng_next_vec2(rng)), ns);
  if (dot(l, ng) <= 0.0) return vec3(0.0);
  return albedo * path_trace(spawn, l, rng, 32u);
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
//   bounce (pdf a delta) adds no spread. Needs the cache (GI_HIT_RADIANCE 2).
struct GlossyPathEnd {
  float spread_a0;
  float first_pdf;  // solid-angle pdf of the primary direction (≥ 1e30: a mirror)
  // 1: count the first hit's emission with weight 1 (DI handed this surface's
  // specular lobe over, specular.di_handover_alpha); 0: DI owns it.
  float first_emission;
};

// The path from a hit onwards (trace_glossy_path of seeds/solari-0.18.md, from
// its first hit): a rough hit ends it in end_path_radiance; a glossy one gets
// NEE (not on mirrors) and a BRDF-sampled bounce, emission found by the
// bounce weighted against NEE by the balance heuristic, for at most
// HIT_GLOSSY_BOUNCES vertices. At the last vertex Solari stops after NEE
// (light beyond it is lost); HIT_SURFACES_FULL ends the path there in
// end_path_radiance instead.
vec3 glossy_path_radiance(Hit hit, vec3 dir, CacheQuery q, GlossyPathEnd path_end, inout uint rng) {
  vec3 radiance = vec3(0.0);
  vec3 throughput = vec3(1.0);
  float previous_pdf = 0.0;  // of the direction just traced; 0: no NEE at its origin (mirror or first vertex)
  float spread = 0.0;
  float spread_pdf = path_end.first_pdf;
  for (uint vertex = 0u;; ++vertex) {
    SurfacePoint s = surface_at_hit(hit);
    bool front = dot(dir, s.geometric_normal) < 0.0;
    if (vertex == 0u && front) radiance += path_end.first_emission * s.emissive;
    if (vertex > 0u && front && max3(s.emissive) > 0.0) {
      float w = previous_pdf > 0.0
                    ? hit_mis(previous_pdf, emissive_hit_light_pdf(s, hit.instance, dir, hit.t))
                    : 1.0;
      radiance += throughput * s.emissive * w;
    }
    vec3 hng = front ? s.geometric_normal : -s.geometric_normal;
    vec3 hns = dot(s.shading_normal, hng) < 0.0 ? -s.shading_normal : s.shading_normal;
    vec3 v = -dir;
    BrdfParams brdf = material_brdf(s.material);
    bool last = vertex + 1u >= uint(HIT_GLOSSY_BOUNCES);
    // HIT_SURFACES_FULL ends the path at its last vertex in the cache, which
    // holds that vertex's direct light too: no NEE there.
    bool end_here = brdf.alpha > float(HIT_GLOSSY_ROUGHNESS) || (HIT_SURFACES_FULL != 0 && last);
#if HIT_RADIANCE == 2
    if (path_end.spread_a0 >= 0.0) {
      spread += sqrt(hit.t * hit.t / (spread_pdf * max(dot(hns, v), 1e-6)));
      end_here = spread * spread > path_end.spread_a0 * world_cache_cell_size(s.position, frame.camera.position.xyz,
                                                                          float(WORLD_CACHE_CELL_SIZE_BASE),
                                                                          float(WORLD_CACHE_LOD_SCALE));
    }
#endif
    if (end_here) {
      radiance += throughput * end_path_radiance(s, hng, hns, v, q, rng);
      break;
    }
    vec3 spawn = offset_ray_origin(s.position, hng);
    bool mirror = brdf.alpha <= SPECULAR_MIRROR_ALPHA;
    if (!mirror) {
      vec3 l;
      float dist;
      vec3 le;
      float light_pdf;
      if (sample_light(s.position, rng, l, dist, le, light_pdf) && dot(l, hng) > 0.0) {
        vec3 f = brdf_eval(brdf, hns, v, l) * max(dot(hns, l), 0.0);
        float w = hit_mis(light_pdf, brdf_pdf(brdf, hns, v, l));
        if (max3(f) > 0.0 && light_sample_visible(s.position, spawn, l, dist))
          radiance += throughput * f * le * (w / light_pdf);
      }
    }
    if (last) break;  // Solari: light beyond the last vertex is lost
    vec3 u = vec3(rng_next_float(rng), rng_next_float(rng), rng_next_float(rng));
    vec3 l;
    float pdf;
    if (!brdf_sample(brdf, hns, v, u, l, pdf) || dot(l, hng) <= 0.0) break;
    throughput *= brdf_eval(brdf, hns, v, l) * (max(dot(hns, l), 0.0) / pdf);
    previous_pdf = mirror ? 0.0 : pdf;
    spread_pdf = mirror ? 1e30 : pdf;
    dir = l;
    if (!trace_closest(spawn, dir, RAY_TMAX, hit)) {
      radiance += throughput * escaped_radiance(dir, previous_pdf);
      break;
    }
  }
  return radiance;
}

// What a GI sample (or a cache cell's GI ray) receives from its hit: Solari
// ("diffuse") ends the path at once; "full" follows a glossy hit along its
// BRDF first, so light that reaches a diffuse surface by way of a mirror or
// glossy metal is not lost.
vec3 secondary_hit_radiance(Hit hit, SurfacePoint s, vec3 ng, vec3 ns, vec3 dir, CacheQuery q, inout uint rng) {
#if HIT_SURFACES_FULL != 0
  return glossy_path_radiance(hit, dir, q, GlossyPathEnd(-1.0, 0.0, 0.0), rng);
#else
  return end_path_radiance(s, ng, ns, -dir, q, rng);
#endif
}
