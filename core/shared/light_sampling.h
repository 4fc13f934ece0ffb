// Generating and resolving light samples against the scene (Solari's
// generate_random_light_sample / resolve_light_sample): bridge-included like
// scene_access.h (include that first; see its header for the accessors).
// The light tiles (gpu/shaders/light_tiles.comp) and the DI reuse passes run it.
//
// Needs from the includer: core/shared/light_tiles.h, reservoir.h, rng.h, sampling.h.

// One light uniformly, one of its triangles uniformly, and a seed for the point.
GI_FN LightSample generate_light_sample(INOUT(uint) rng) {
  LightSample s;
  uint count = scene_light_count();
  s.valid = 0u;
  s.light_id = 0u;
  s.triangle_id = 0u;
  s.seed = 0u;
  if (count == 0u) return s;
  s.light_id = min(uint(rng_next_float(rng) * float(count)), max(count, 1u) - 1u);
  GpuLight light = scene_light(s.light_id);
  if (light.kind != LIGHT_KIND_DIRECTIONAL)
    s.triangle_id = min(uint(rng_next_float(rng) * float(light.triangle_count)), light.triangle_count - 1u);
  s.seed = rng_next_uint(rng);
  s.valid = 1u;
  return s;
}

// Full precision; the radiance is the scene's (encoding is the caller's choice).
GI_FN ResolvedLightSample resolve_light_sample(LightSample ls) {
  ResolvedLightSample r;
  uint rng = ls.seed;
  vec2 u = rng_next_vec2(rng);
  GpuLight light = scene_light(ls.light_id);
  float count = float(scene_light_count());
  if (light.kind == LIGHT_KIND_DIRECTIONAL) {
#ifdef LIGHT_SUN_CENTER
    // Solari 0.17's hard sun (v0.17.0:scene/sampling.wgsl:122-138, the cone
    // only under a define nothing set): the centre direction, the cone's
    // weight, so the irradiance is right and the penumbra is gone.
    vec3 dir = vec3(light.direction);
#else
    vec3 dir = to_world(sample_cone(u, light.direction.w), vec3(light.direction));
#endif
    r.world_position = vec4(dir, 0.0f);
    r.world_normal = -dir;
    r.radiance = vec3(light.radiance);
    r.inverse_pdf = count * cone_solid_angle(light.direction.w);
    return r;
  }
  SurfacePoint q = surface_at(light.instance, ls.triangle_id, sample_triangle(u));
  r.world_position = vec4(q.position, 1.0f);
  r.world_normal = q.geometric_normal;
  r.radiance = q.emissive;
  r.inverse_pdf = count * float(light.triangle_count) * q.area;
  return r;
}

// The scene's radiance taken through the light tiles' encoding (packing.h):
// what a tile sample carries. Bevy's DI re-resolves reused samples in full
// precision (resolve_light_sample above); this is the world cache's random
// sample and, under restir_di.reuse_radiance "tile_encoding" (the harness's
// earlier model), every DI evaluation's (docs/findings/restir-di.md, "The
// tile encoding").
GI_FN ResolvedLightSample resolve_light_sample_encoded(LightSample ls, float exposure, bool log2_radiance) {
  ResolvedLightSample r = resolve_light_sample(ls);
  r.radiance = unpack_radiance(pack_radiance(r.radiance, exposure, log2_radiance), exposure, log2_radiance);
  return r;
}

// Shadow ray from a surface point (geometric normal ng facing the light's side)
// to a resolved sample: aimed from the offset origin at the light point, as
// path_integrator.h's next-event estimation does. False when the light is
// behind the surface (no ray).
GI_FN bool light_sample_shadow_ray(vec3 position, vec3 ng, ResolvedLightSample s, OUT(vec3) spawn, OUT(vec3) dir,
                                   OUT(float) tmax) {
  LightContribution c = light_contribution(s, position, ng);
  if (dot(c.wi, ng) <= 0.0f) return false;
  spawn = offset_ray_origin(position, ng);
  dir = c.wi;
  tmax = RAY_TMAX;
  if (s.world_position.w != 0.0f) {
    vec3 to_light = vec3(s.world_position) - spawn;
    float dist = length(to_light);
    dir = to_light / dist;
    tmax = dist * (1.0f - 1e-4f);
  }
  return true;
}

// Whether the sample lights the point. One trace call for both kinds of
// light: the shader compiler inlines the whole traversal at every call
// (core/shared/bvh_traverse.h).
GI_FN bool light_sample_visible(vec3 position, vec3 ng, ResolvedLightSample s) {
  vec3 spawn, dir;
  float tmax;
  return light_sample_shadow_ray(position, ng, s, spawn, dir, tmax) && trace_unoccluded(spawn, dir, tmax);
}
