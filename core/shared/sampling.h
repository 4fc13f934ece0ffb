// Sampling routines with their pdfs (solid angle unless the name says area).
#ifndef GI_SHARED_SAMPLING_H
#define GI_SHARED_SAMPLING_H
#include "host_device.h"

GI_SHADER_BEGIN

// Orthonormal basis around n (Duff et al., "Building an Orthonormal Basis,
// Revisited", JCGT 2017): branchless and continuous except at n.z = -1 sign flip.
GI_FN void orthonormal_basis(vec3 n, OUT(vec3) t, OUT(vec3) b) {
  float s = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

GI_FN vec3 to_world(vec3 local, vec3 n) {
  vec3 t;
  vec3 b;
  orthonormal_basis(n, t, b);
  return local.x * t + local.y * b + local.z * n;
}

GI_FN vec3 from_world(vec3 w, vec3 n) {
  vec3 t;
  vec3 b;
  orthonormal_basis(n, t, b);
  return vec3(dot(w, t), dot(w, b), dot(w, n));
}

// Cosine-weighted hemisphere around +z; pdf = cos(theta) / pi.
GI_FN vec3 sample_cosine_hemisphere(vec2 u) {
  float r = sqrt(u.x);
  float phi = TWO_PI * u.y;
  return vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0f, 1.0f - u.x)));
}

// Uniform hemisphere around +z; pdf = 1 / (2 pi).
GI_FN vec3 sample_uniform_hemisphere(vec2 u) {
  float z = u.x;
  float r = sqrt(max(0.0f, 1.0f - z * z));
  float phi = TWO_PI * u.y;
  return vec3(r * cos(phi), r * sin(phi), z);
}

// 1 - cos(theta) without cancellation for tiny angles (sun-sized cones).
GI_FN float one_minus_cos(float theta) {
  float s = sin(0.5f * theta);
  return 2.0f * s * s;
}

// Uniform direction in a cone of half-angle theta_max around +z;
// pdf = 1 / (2 pi (1 - cos theta_max)).
GI_FN vec3 sample_cone(vec2 u, float one_minus_cos_max) {
  float one_minus_cos_theta = u.x * one_minus_cos_max;
  float cos_theta = 1.0f - one_minus_cos_theta;
  float sin_theta = sqrt(max(0.0f, one_minus_cos_theta * (2.0f - one_minus_cos_theta)));
  float phi = TWO_PI * u.y;
  return vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}

GI_FN float cone_solid_angle(float one_minus_cos_max) { return TWO_PI * one_minus_cos_max; }

// Uniform point on a triangle as barycentrics (b1, b2) of p1, p2
// (Heitz, "A Low-Distortion Map Between Triangle and Square", 2019).
GI_FN vec2 sample_triangle(vec2 u) {
  vec2 b;
  if (u.y > u.x) {
    b.x = u.x * 0.5f;
    b.y = u.y - b.x;
  } else {
    b.y = u.y * 0.5f;
    b.x = u.x - b.y;
  }
  return b;
}

// Multiple importance sampling (Veach).
GI_FN float balance_heuristic(float a, float b) { return a / (a + b); }
// Veach's power heuristic with β = 2 (Solari's specular GI, v0.18.0
// realtime/specular_gi.wgsl:147,170).
GI_FN float power_heuristic(float a, float b) { return (a * a) / (a * a + b * b); }

// How add_next_event() (path_integrator.h) weighs its light sample against BRDF sampling.
GI_CONST uint MIS_NONE = 0u;     // light sampling alone (no BRDF-sampled twin)
GI_CONST uint MIS_BALANCE = 1u;  // the reference path tracer's
GI_CONST uint MIS_POWER = 2u;    // Solari 0.18's glossy path (specular.mis "power")
// Or-ed onto a heuristic: the light's pdf enters the weight in area measure
// at the light point while the BRDF's stays in solid angle, as Solari's
// glossy path weighed them before #24671 (specular.mis_light_pdf "area").
// Both strategies weigh the same pair, so the weights still sum to one: the
// mean stays, the noise grows with the light's distance.
GI_CONST uint MIS_LIGHT_PDF_AREA = 0x100u;
// Or-ed onto a heuristic: a directional light's NEE sample has weight 1, as
// no BRDF-sampled ray is counted as reaching it (Solari's glossy path:
// brdf_rays_can_hit false); the includer adds no escaped light then
// (specular.directional_lights "nee_only").
GI_CONST uint MIS_DIRECTIONAL_UNWEIGHTED = 0x200u;
GI_CONST uint MIS_KIND = 0xFFu;  // the heuristic without the bits above

GI_FN float mis_weight(uint heuristic, float a, float b) {
  return (heuristic & MIS_KIND) == MIS_POWER ? power_heuristic(a, b) : balance_heuristic(a, b);
}

GI_SHADER_END

#endif
