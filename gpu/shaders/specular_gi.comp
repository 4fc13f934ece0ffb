// Specular GI (DESIGN §3 step 8; seeds/solari-0.18.md "Specular GI"): the
// specular lobe's indirect light at each pixel.
// - alpha > SPECULAR_REUSE_ROUGHNESS: reuse this frame's final GI reservoir
//   (its direction and radiance · W) with the specular BRDF.
// - else sample GGX with bounded VNDF (the mirror special case at alpha ≤
//   0.001) and trace_glossy_path: up to SPECULAR_MAX_BOUNCES bounces;
//   emissive hits count from the second vertex on (DI owns the first), NEE
//   at non-mirror vertices, balance-heuristic MIS between the two, a rough
//   hit ends the path in gi_hit_radiance (GI_HIT_RADIANCE 2: the world cache,
//   pixel-rooted, as Solari).
// The primary surface's roughness is clamped by SPECULAR_MIN_PERCEPTUAL_ROUGHNESS
// (brdf.min_perceptual_roughness; 0 = Solari 0.17, NaN on zero roughness).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/shaders/gi_common.glsl"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_GI_RESERVOIRS_STORED) readonly buffer Stored { GiReservoir stored_reservoirs[]; };
layout(std430, set = 0, binding = BINDING_SPECULAR_OUTPUT) writeonly buffer Output { vec4 specular_output[]; };
layout(std430, set = 0, binding = BINDING_SPECULAR_ACCUMULATION) buffer Accumulation { vec4 specular_accumulation[]; };

// Radiance arriving at `position` along `dir`, without what DI owns (the
// first vertex's emission and escaped light).
vec3 trace_glossy_path(vec3 position, vec3 ng, vec3 dir, uint query_id, inout uint rng) {
  vec3 radiance = vec3(0.0);
  vec3 throughput = vec3(1.0);
  float previous_pdf = 0.0;  // of the direction just traced; 0: no NEE at its origin (mirror or bounce 0)
  vec3 origin = offset_ray_origin(position, ng);
  for (uint bounce = 0u; bounce < uint(SPECULAR_MAX_BOUNCES); ++bounce) {
    Hit hit;
    if (!trace_closest(origin, dir, RAY_TMAX, hit)) {
      if (bounce > 0u) radiance += throughput * escaped_radiance(dir, previous_pdf);
      break;
    }
    SurfacePoint s = surface_at_hit(hit);
    bool front = dot(dir, s.geometric_normal) < 0.0;
    if (bounce > 0u && front && max3(s.emissive) > 0.0) {
      float w = previous_pdf > 0.0
                    ? balance_heuristic(previous_pdf, emissive_hit_light_pdf(s, hit.instance, dir, hit.t))
                    : 1.0;
      radiance += throughput * s.emissive * w;
    }
    vec3 hng = front ? s.geometric_normal : -s.geometric_normal;
    vec3 hns = dot(s.shading_normal, hng) < 0.0 ? -s.shading_normal : s.shading_normal;
    BrdfParams brdf = material_brdf(s.material);
    if (brdf.alpha > float(SPECULAR_REUSE_ROUGHNESS)) {
      radiance += throughput * gi_hit_radiance(s, hng, hns, query_id, rng);
      break;
    }
    vec3 v = -dir;
    vec3 spawn = offset_ray_origin(s.position, hng);
    bool mirror = brdf.alpha <= SPECULAR_MIRROR_ALPHA;
    if (!mirror) {
      vec3 l;
      float dist;
      vec3 le;
      float light_pdf;
      if (sample_light(s.position, rng, l, dist, le, light_pdf) && dot(l, hng) > 0.0) {
        vec3 f = brdf_eval(brdf, hns, v, l) * max(dot(hns, l), 0.0);
        if (max3(f) > 0.0 && light_sample_visible(s.position, spawn, l, dist))
          radiance += throughput * f * le * (balance_heuristic(light_pdf, brdf_pdf(brdf, hns, v, l)) / light_pdf);
      }
    }
    vec3 u = vec3(rng_next_float(rng), rng_next_float(rng), rng_next_float(rng));
    vec3 l;
    float pdf;
    if (!brdf_sample(brdf, hns, v, u, l, pdf) || dot(l, hng) <= 0.0) break;
    throughput *= brdf_eval(brdf, hns, v, l) * (max(dot(hns, l), 0.0) / pdf);
    previous_pdf = mirror ? 0.0 : pdf;
    origin = spawn;
    dir = l;
  }
  return radiance;
}

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  uint chain = gl_GlobalInvocationID.z;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;
  uint slot = chain * resolution.x * resolution.y + index;
  GiPixel d = gi_pixel(pixel);
  vec3 color = vec3(0.0);
  if (d.hit) {
    uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_SPECULAR + chain, index, frame.resolution_frame.z);
    vec3 f0 = vec3(0.16 * d.reflectance * d.reflectance * (1.0 - d.metallic)) + d.base_color * d.metallic;
    float alpha = specular_alpha(d.perceptual_roughness, float(SPECULAR_MIN_PERCEPTUAL_ROUGHNESS));
    if (alpha > float(SPECULAR_REUSE_ROUGHNESS)) {
      GiReservoir r = stored_reservoirs[slot];
      if (gi_reservoir_valid(r)) {
        vec3 wi = normalize(r.sample_position.xyz - d.position);
        color = specular_brdf(f0, alpha, d.ns, d.view, wi) * max(dot(d.ns, wi), 0.0) * r.radiance.rgb * r.radiance.w;
      }
    } else if (max3(f0) > 0.0) {
      vec3 wi = to_world(sample_ggx_bounded_vndf(from_world(d.view, d.ns), alpha, rng_next_vec2(rng)), d.ns);
      if (dot(wi, d.ng) > 0.0 && dot(wi, d.ns) > 0.0)
        color = specular_sample_weight(f0, alpha, d.ns, d.view, wi) * trace_glossy_path(d.position, d.ng, wi, gi_cache_query_id(1u, chain, index), rng);
    }
  }
  if (!(gi_finite(color.r) && gi_finite(color.g) && gi_finite(color.b))) atomicAdd(gi_stats.nonfinite_output, 1u);
  specular_output[slot] = vec4(color, d.hit ? 1.0 : 0.0);
  if (push.accumulate != 0u) specular_accumulation[slot] += vec4(color, 1.0);
}
