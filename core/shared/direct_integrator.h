// "DI" as both the realtime pipeline and the reference define it (README,
// "Realtime mode"): the radiance emitted towards the camera by the primary hit
// (front faces only) plus the direct light that hit reflects — every emitter
// and directional light, shadowed, with the full BRDF (brdf.h) times the
// cosine at the shading normal, light arriving from below the geometric
// normal excluded. No indirect light, no emitter seen through a reflection.
//
// direct_trace() estimates it with light sampling only (sample_light of
// path_integrator.h, no BRDF sampling, no MIS): the Embree reference's
// direct-lighting mode. Bridge-included after path_integrator.h.

GI_FN vec3 direct_trace(vec3 origin, vec3 direction, INOUT(uint) rng) {
  Hit hit;
  if (!trace_closest(origin, direction, RAY_TMAX, hit)) return escaped_radiance(direction, 0.0f);
  SurfacePoint s = surface_at_hit(hit);
  bool front = dot(direction, s.geometric_normal) < 0.0f;
  vec3 radiance = front ? s.emissive : vec3(0.0f);
  vec3 ng = front ? s.geometric_normal : -s.geometric_normal;
  vec3 ns = dot(s.shading_normal, ng) < 0.0f ? -s.shading_normal : s.shading_normal;
  vec3 v = -direction;
  BrdfParams brdf = surface_brdf(s);
  vec3 spawn = offset_ray_origin(s.position, ng);
  add_next_event(brdf, s.position, ng, ns, v, spawn, vec3(1.0f), MIS_NONE, radiance, rng);
  return radiance;
}
