// World cache update, indirect light (docs/design.md §3 step 5; Solari's
// sample_irradiance, 2nd ray): per active cell a cosine-distributed ray of at
// most WORLD_CACHE_GI_TMAX; at a hit, the hit's albedo times the
// cache there (a cache-to-cache query: life by the profile's rule, root frame
// passed on). Irradiance estimate: π · (ρ/π) · E_hit = ρ · E_hit, ρ the
// brdf.secondary_albedo (Bevy's: full base colour). Emission at
// the hit is left out: the direct sample owns the lights.
// WORLD_CACHE_SECONDARY_HITS_FULL (brdf.secondary_hits "full"): π times the
// hit's secondary_hit_radiance instead (hit_radiance.glsl: a glossy hit is
// followed along its BRDF before the path queries the cache).
#version 460
#extension GL_GOOGLE_include_directive : require
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"
#include "core/shared/path_integrator.h"
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/world_cache_query.glsl"

#ifndef WORLD_CACHE_GI_REACH_COSINE
#define WORLD_CACHE_GI_REACH_COSINE 0  // world_cache.gi_ray_direction "normalised"
#endif
#define HIT_RADIANCE 2
#define HIT_SURFACES_FULL WORLD_CACHE_SECONDARY_HITS_FULL
#define HIT_GLOSSY_ROUGHNESS WORLD_CACHE_GLOSSY_ROUGHNESS
#define HIT_GLOSSY_BOUNCES WORLD_CACHE_GLOSSY_BOUNCES
#define HIT_ALBEDO_BASE WORLD_CACHE_SECONDARY_ALBEDO_BASE
#define HIT_CACHE_NORMAL_VERTEX WORLD_CACHE_HIT_NORMAL_VERTEX
#define HIT_POWER_MIS 0  // the cache's GI ray follows glossy hits only under brdf.secondary_hits full (harness)
#include "gpu/shaders/hit_radiance.glsl"

layout(local_size_x = WORLD_CACHE_UPDATE_GROUP) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= wc_counters.active_args.w) return;
  if (wc_new_radiance[i].w != 0.0) return;  // left out by the soft cap (world_cache_sample_di)
  uint cell = wc_active[i];
  uvec2 state = wc_active_state[i];  // (life, root frame) before this frame's queries
  vec3 p = wc_geometry[cell].position.xyz;
  vec3 n = wc_geometry[cell].normal.xyz;
  uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_WORLD_CACHE_GI, wc_checksums[cell], frame.resolution_frame.z);
  vec3 dir = to_world(sample_cosine_hemisphere(rng_next_vec2(rng)), n);
  Hit hit;
  vec3 irradiance = vec3(0.0);
#if WORLD_CACHE_GI_REACH_COSINE != 0
  // Solari 0.17 and 0.18 trace bevy_pbr's cosine sample n + u unnormalised
  // (v0.18.0:crates/bevy_pbr/src/render/utils.wgsl:98-106, traced at
  // v0.18.0:realtime/world_cache_update.wgsl:38-39), and a ray query's t is
  // parametric: the ray reaches tmax |n + u| = 2 cos(angle to n) tmax.
  float gi_tmax = float(WORLD_CACHE_GI_TMAX) * 2.0 * dot(dir, n);
#else
  float gi_tmax = float(WORLD_CACHE_GI_TMAX);
#endif
  if (trace_closest(offset_ray_origin(p, n), dir, gi_tmax, hit)) {
    SurfacePoint s = surface_at_hit(hit);
    vec3 hit_position = s.position;
    vec3 hit_normal = dot(s.geometric_normal, dir) > 0.0 ? -s.geometric_normal : s.geometric_normal;
    uint life = world_cache_query_life(false, state.x, uint(WORLD_CACHE_LIFETIME), WORLD_CACHE_C2C_FULL != 0);
#if WORLD_CACHE_SECONDARY_HITS_FULL != 0
    CacheQuery q;
    q.life = life;
    q.root_frame = state.y;
    q.id = cell;
    q.list = 0u;
    q.first_bounce = 0u;
    vec3 ns = dot(s.shading_normal, hit_normal) < 0.0 ? -s.shading_normal : s.shading_normal;
    irradiance = PI * secondary_hit_radiance(hit, s, hit_normal, ns, dir, q, rng);
#else
    // Solari's formula (ρ · E, not π · ρ/π · E through end_path_radiance).
    // ρ is brdf.secondary_albedo: the full base colour, metallic ignored, as
    // Bevy's world_cache_update.wgsl does; "diffuse" keeps the harness's
    // earlier base·(1−metallic), under which a metal wall adds nothing.
#if HIT_ALBEDO_BASE != 0
    vec3 albedo = s.base_color_metallic.rgb;
#else
    vec3 albedo = s.base_color_metallic.rgb * (1.0 - s.base_color_metallic.a);
#endif
    irradiance = albedo * world_cache_query(hit_position, hit_cache_normal(s, hit_normal), hit.t, false, life, state.y, cell, 0u, rng);
#endif
  }
  wc_new_radiance[i] += vec4(irradiance, 0.0);
}
