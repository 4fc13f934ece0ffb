// The unbiased reference path tracer: next-event estimation + BRDF sampling,
// combined with the balance heuristic, Russian roulette after 3 bounces.
// The GPU reference mode (gpu/shaders/reference_path_trace.comp) and the Embree
// reference (core/reference/) both run this code; they differ in how rays are
// traced, in their random streams, and in nothing else.
//
// Bridge-included like scene_access.h (include that first). Extra accessors:
//   bool trace_closest(vec3 origin, vec3 dir, float tmax, OUT(Hit) hit);
//   bool trace_unoccluded(vec3 origin, vec3 dir, float tmax);

// Spawn offset along the geometric normal, scaled with the coordinates' size so
// it stays above float rounding far from the origin.
GI_FN vec3 offset_ray_origin(vec3 p, vec3 n) {
  float scale = max(1.0f, max3(abs(p)));
  return p + n * (1e-4f * scale);
}

// Shadow test for a light sample (direction l, distance dist from p; dist =
// RAY_TMAX for directional lights) from the offset origin `spawn`. The ray
// aims from `spawn` at the light point itself: the segment meets the
// emitter's plane only at its end, so a relative margin works at any
// distance from the world origin.
GI_FN bool light_sample_visible(vec3 p, vec3 spawn, vec3 l, float dist) {
  // One trace call for both kinds of light (light_sampling.h says why).
  vec3 dir = l;
  float tmax = RAY_TMAX;
  if (!(dist >= RAY_TMAX)) {
    vec3 to_light = p + l * dist - spawn;
    float shadow_dist = length(to_light);
    dir = to_light / shadow_dist;
    tmax = shadow_dist * (1.0f - 1e-4f);
  }
  return trace_unoccluded(spawn, dir, tmax);
}

// Picks one light uniformly, then a triangle, then a point (or a direction in
// a directional light's cone). pdf is in solid angle at p, selection included;
// area_pdf the same choice in area measure at the light point (a directional
// light's is its solid-angle pdf).
GI_FN bool sample_light(vec3 p, INOUT(uint) rng, OUT(vec3) dir, OUT(float) dist, OUT(vec3) radiance,
                        OUT(float) pdf, OUT(float) area_pdf) {
  uint count = scene_light_count();
  if (count == 0u) return false;
  uint index = min(uint(rng_next_float(rng) * float(count)), count - 1u);
  GpuLight light = scene_light(index);
  vec2 u = rng_next_vec2(rng);
  float pick = rng_next_float(rng);
  if (light.kind == LIGHT_KIND_DIRECTIONAL) {
    dir = to_world(sample_cone(u, light.direction.w), vec3(light.direction));
    dist = RAY_TMAX;
    radiance = vec3(light.radiance);
    pdf = 1.0f / (float(count) * cone_solid_angle(light.direction.w));
    area_pdf = pdf;
    return true;
  }
  uint tri = min(uint(pick * float(light.triangle_count)), light.triangle_count - 1u);
  SurfacePoint q = surface_at(light.instance, tri, sample_triangle(u));
  vec3 d = q.position - p;
  float dist2 = dot(d, d);
  if (dist2 <= 0.0f || q.area <= 0.0f) return false;
  dist = sqrt(dist2);
  dir = d / dist;
  float cos_light = -dot(dir, q.geometric_normal);  // emitters shine from the front face only
  if (cos_light <= 0.0f) return false;
  radiance = q.emissive;
  pdf = dist2 / (cos_light * float(count) * float(light.triangle_count) * q.area);
  area_pdf = 1.0f / (float(count) * float(light.triangle_count) * q.area);
  return true;
}

// Next-event estimation at a shading point (position p, geometric normal ng
// and shading normal ns on the side the ray arrived from, v towards where it
// came from, spawn the offset origin): one light sample, shadowed, times the
// BRDF and the cosine at ns, over its pdf, weighted against BRDF sampling by
// `heuristic` (with MIS_LIGHT_PDF_AREA: the light's area-measure pdf in the
// weight; with MIS_DIRECTIONAL_UNWEIGHTED: a directional light's sample at weight 1);
// light from below ng is excluded. Adds throughput times that to
// `radiance` (inside the test, as one multiply-add: the shader compiler fuses
// it there, and the GPU images keep their bits).
GI_FN void add_next_event(BrdfParams brdf, vec3 p, vec3 ng, vec3 ns, vec3 v, vec3 spawn, vec3 throughput,
                          uint heuristic, INOUT(vec3) radiance, INOUT(uint) rng) {
  vec3 l;
  float dist;
  vec3 le;
  float light_pdf;
  float light_area_pdf;
  if (sample_light(p, rng, l, dist, le, light_pdf, light_area_pdf) && dot(l, ng) > 0.0f) {
    vec3 f = brdf_eval(brdf, ns, v, l) * max(dot(ns, l), 0.0f);
    if (max3(f) > 0.0f && light_sample_visible(p, spawn, l, dist)) {
      if (heuristic == MIS_NONE) {
        radiance += throughput * f * le / light_pdf;
      } else {
        float weighed = (heuristic & MIS_LIGHT_PDF_AREA) != 0u ? light_area_pdf : light_pdf;
        bool unweighted = (heuristic & MIS_DIRECTIONAL_UNWEIGHTED) != 0u && dist >= RAY_TMAX;
        float w = unweighted ? 1.0f : mis_weight(heuristic, weighed, brdf_pdf(brdf, ns, v, l));
        radiance += throughput * f * le * (w / light_pdf);
      }
    }
  }
}

// Solid-angle pdf with which sample_light would have produced this emitter hit.
GI_FN float emissive_hit_light_pdf(SurfacePoint s, uint instance_index, vec3 dir, float t) {
  GpuInstance inst = scene_instance(instance_index);
  float cos_light = -dot(dir, s.geometric_normal);
  if (cos_light <= 0.0f || s.area <= 0.0f) return 0.0f;
  return t * t / (cos_light * float(scene_light_count()) * float(inst.triangle_count) * s.area);
}

// Radiance arriving along a ray that escaped the scene: the directional lights
// whose cone contains it, weighted against light sampling unless the ray was
// not BRDF-sampled (camera rays: brdf_pdf = 0).
GI_FN vec3 escaped_radiance(vec3 dir, float brdf_pdf_value) {
  vec3 sum = vec3(0.0f);
  uint count = scene_light_count();
  uint directional = scene_directional_light_count();
  for (uint i = 0u; i < directional; ++i) {
    GpuLight light = scene_light(i);
    if (1.0f - dot(dir, vec3(light.direction)) > light.direction.w) continue;
    float w = 1.0f;
    if (brdf_pdf_value > 0.0f)
      w = balance_heuristic(brdf_pdf_value, 1.0f / (float(count) * cone_solid_angle(light.direction.w)));
    sum += w * vec3(light.radiance);
  }
  return sum;
}

// The BRDF at a surface point: its textured colour, metallic and roughness,
// the material's reflectance and model.
GI_FN BrdfParams surface_brdf(SurfacePoint s) {
  GpuMaterial m = scene_material(s.material);
  return brdf_params(vec3(s.base_color_metallic), s.base_color_metallic.w, s.perceptual_roughness, m.reflectance.x,
                     uint(m.reflectance.y));
}

// Radiance along one camera ray. max_bounces caps the path length (Russian
// roulette ends nearly every path long before; the cap is shared by both
// renderers, so it biases neither against the other).
GI_FN vec3 path_trace(vec3 origin, vec3 direction, INOUT(uint) rng, uint max_bounces) {
  vec3 radiance = vec3(0.0f);
  vec3 throughput = vec3(1.0f);
  float previous_brdf_pdf = 0.0f;  // 0: the ray was not BRDF-sampled (camera ray)
  for (uint bounce = 0u; bounce < max_bounces; ++bounce) {
    Hit hit;
    if (!trace_closest(origin, direction, RAY_TMAX, hit)) {
      radiance += throughput * escaped_radiance(direction, previous_brdf_pdf);
      break;
    }
    SurfacePoint s = surface_at_hit(hit);
    bool front = dot(direction, s.geometric_normal) < 0.0f;
    if (front && max3(s.emissive) > 0.0f) {
      float w = 1.0f;
      if (previous_brdf_pdf > 0.0f)
        w = balance_heuristic(previous_brdf_pdf,
                              emissive_hit_light_pdf(s, hit.instance, direction, hit.t));
      radiance += throughput * s.emissive * w;
    }

    // Shade on the side the ray arrived from.
    vec3 ng = front ? s.geometric_normal : -s.geometric_normal;
    vec3 ns = dot(s.shading_normal, ng) < 0.0f ? -s.shading_normal : s.shading_normal;
    vec3 v = -direction;
    BrdfParams brdf = surface_brdf(s);
    vec3 spawn = offset_ray_origin(s.position, ng);

    add_next_event(brdf, s.position, ng, ns, v, spawn, throughput, MIS_BALANCE, radiance, rng);

    // BRDF sampling continues the path.
    vec3 u = vec3(rng_next_float(rng), rng_next_float(rng), rng_next_float(rng));
    vec3 l;
    float pdf;
    if (!brdf_sample(brdf, ns, v, u, l, pdf)) break;
    if (dot(l, ng) <= 0.0f) break;
    throughput *= brdf_eval(brdf, ns, v, l) * (max(dot(ns, l), 0.0f) / pdf);
    previous_brdf_pdf = pdf;

    if (bounce >= 3u) {
      float survive = min(max3(throughput), 0.95f);
      if (rng_next_float(rng) >= survive) break;
      throughput /= survive;
    }
    origin = spawn;
    direction = l;
  }
  return radiance;
}
