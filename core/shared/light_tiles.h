// Light tiles (docs/design.md §3 step 4; Wyman & Panteleev, "Rearchitecting
// Spatiotemporal Resampling for Production", HPG 2021, §5): resolved light
// samples packed into 24 bytes, shared by the GPU passes and the CPU tests
// (host_device.h rules).
#ifndef GI_SHARED_LIGHT_TILES_H
#define GI_SHARED_LIGHT_TILES_H
#include "host_device.h"
#include "packing.h"

GI_SHADER_BEGIN

// A light sample resolved against the scene.
struct ResolvedLightSample {
  vec4 world_position;  // w = 1: a point on an emitter; w = 0: xyz is the unit direction to a directional light
  vec3 world_normal;    // emitter normal (front face); −direction for directional lights
  vec3 radiance;
  float inverse_pdf;    // area measure for emitters (light_count·triangle_count·area), solid angle for directional
};

// 24 bytes: 6 scalars, so std430 and C++ agree without padding.
struct PackedLightSample {
  float position_x;
  float position_y;
  float position_z;
  uint normal;         // octahedral, 2 × unorm16
  uint radiance;       // rgb9e5, plain or of log2(L·exposure + 1)
  float inverse_pdf;   // negative: directional light
};

GI_FN PackedLightSample pack_light_sample(ResolvedLightSample s, float exposure, bool log2_radiance) {
  PackedLightSample p;
  p.position_x = s.world_position.x;
  p.position_y = s.world_position.y;
  p.position_z = s.world_position.z;
  p.normal = pack_unit_vector(s.world_normal);
  p.radiance = pack_radiance(s.radiance, exposure, log2_radiance);
  p.inverse_pdf = s.world_position.w == 0.0f ? -s.inverse_pdf : s.inverse_pdf;
  return p;
}

GI_FN ResolvedLightSample unpack_light_sample(PackedLightSample p, float exposure, bool log2_radiance) {
  ResolvedLightSample s;
  s.world_position = vec4(p.position_x, p.position_y, p.position_z, p.inverse_pdf < 0.0f ? 0.0f : 1.0f);
  s.world_normal = unpack_unit_vector(p.normal);
  s.radiance = unpack_radiance(p.radiance, exposure, log2_radiance);
  s.inverse_pdf = abs(p.inverse_pdf);
  return s;
}

// What a light sample delivers to a receiving point, unshadowed.
struct LightContribution {
  vec3 received_radiance;  // L · cos(receiver) · cos(light) / d²  (directional: L · cos(receiver))
  float inverse_pdf;
  vec3 wi;                 // unit direction to the light
  float distance;          // RAY_TMAX-like 1e20 for directional lights
};

// Solari's calculate_resolved_light_contribution, with emitters shining from
// the front face only and the receiver's cosine against its shading normal.
GI_FN LightContribution light_contribution(ResolvedLightSample s, vec3 origin, vec3 normal) {
  LightContribution c;
  vec3 ray = vec3(s.world_position) - s.world_position.w * origin;
  float d = length(ray);
  c.wi = d > 0.0f ? ray / d : vec3(0.0f, 0.0f, 1.0f);
  c.distance = s.world_position.w == 0.0f ? 1e20f : d;
  float cos_origin = saturate(dot(c.wi, normal));
  float cos_light = saturate(dot(-c.wi, s.world_normal));
  float geometry = s.world_position.w == 0.0f ? 1.0f : cos_light / max(d * d, 1e-20f);
  c.received_radiance = s.radiance * (cos_origin * geometry);
  c.inverse_pdf = s.inverse_pdf;
  return c;
}

GI_SHADER_END

#endif
