// The material model both renderers shade with (DESIGN §3, "Materials"):
// Lambert diffuse + GGX specular with Smith height-correlated visibility and
// Schlick Fresnel, F0 from base colour, metallic and reflectance
// (Filament / Bevy StandardMaterial conventions), roughness = perceptual².
// Multiscatter energy compensation is not modelled yet (README, "Design notes").
#ifndef GI_SHARED_BRDF_H
#define GI_SHARED_BRDF_H
#include "host_device.h"
#include "sampling.h"

GI_SHADER_BEGIN

// 0.18 clamps perceptual roughness to >= 0.0316 (roughness 0.001): below it
// D_GGX overflows in float and zero roughness gives NaN (Solari 0.18 post).
GI_CONST float MIN_PERCEPTUAL_ROUGHNESS = 0.0316f;

struct BrdfParams {
  vec3 diffuse_color;  // base_color * (1 - metallic)
  vec3 f0;             // 0.16 reflectance² (1 - metallic) + base_color metallic
  float alpha;         // perceptual_roughness², after the clamp
};

GI_FN BrdfParams brdf_params(vec3 base_color, float metallic, float perceptual_roughness,
                             float reflectance) {
  BrdfParams p;
  p.diffuse_color = base_color * (1.0f - metallic);
  p.f0 = vec3(0.16f * reflectance * reflectance * (1.0f - metallic)) + base_color * metallic;
  float r = max(perceptual_roughness, MIN_PERCEPTUAL_ROUGHNESS);
  p.alpha = r * r;
  return p;
}

GI_FN float D_GGX(float alpha, float NoH) {
  float a2 = alpha * alpha;
  float d = NoH * NoH * (a2 - 1.0f) + 1.0f;
  return a2 / (PI * d * d);
}

// Heitz 2014, height-correlated Smith, folded with 1 / (4 NoV NoL).
GI_FN float V_SmithGGXCorrelated(float alpha, float NoV, float NoL) {
  float a2 = alpha * alpha;
  float lv = NoL * sqrt(NoV * NoV * (1.0f - a2) + a2);
  float ll = NoV * sqrt(NoL * NoL * (1.0f - a2) + a2);
  return 0.5f / (lv + ll);
}

GI_FN float smith_G1(float alpha, float NoV) {
  float a2 = alpha * alpha;
  return 2.0f * NoV / (NoV + sqrt(a2 + (1.0f - a2) * NoV * NoV));
}

// Schlick with Filament's (and Bevy's) f90 = saturate(50 · 0.33 · sum(f0)):
// reflectance below ~2% fades the grazing reflection out, so reflectance 0
// is a pure Lambert surface (the Cornell box) instead of one that still
// reflects up to 100% at grazing angles.
GI_FN vec3 F_Schlick(vec3 f0, float VoH) {
  float f90 = saturate(dot(f0, vec3(50.0f * 0.33f)));
  float f = pow(1.0f - saturate(VoH), 5.0f);
  return f0 + (vec3(f90) - f0) * f;
}

// Cosines below this count as grazing; keeps every division finite.
GI_CONST float BRDF_MIN_COS = 1e-6f;

// The specular lobe (D_GGX · V_SmithGGXCorrelated · F_Schlick) at a given
// alpha, n facing v. No clamp here: alpha = 0 at the mirror direction
// is D_GGX = 0/0.
GI_FN vec3 specular_brdf(vec3 f0, float alpha, vec3 n, vec3 v, vec3 l) {
  float NoL = dot(n, l);
  if (NoL <= 0.0f) return vec3(0.0f);
  float NoV = max(dot(n, v), BRDF_MIN_COS);
  vec3 h = normalize(v + l);
  float NoH = saturate(dot(n, h));
  float VoH = saturate(dot(v, h));
  return D_GGX(alpha, NoH) * V_SmithGGXCorrelated(alpha, NoV, NoL) * F_Schlick(f0, VoH);
}

// f(v, l) (without the cosine), n the shading normal facing v.
GI_FN vec3 brdf_eval(BrdfParams p, vec3 n, vec3 v, vec3 l) {
  if (dot(n, l) <= 0.0f) return vec3(0.0f);
  return p.diffuse_color * INV_PI + specular_brdf(p.f0, p.alpha, n, v, l);
}

// The diffuse lobe alone (Solari's evaluate_diffuse_brdf).
GI_FN vec3 brdf_eval_diffuse(BrdfParams p, vec3 n, vec3 l) {
  return dot(n, l) > 0.0f ? p.diffuse_color * INV_PI : vec3(0.0f);
}

// Probability of sampling the specular lobe; depends on v only, so sampling
// and pdf evaluation agree. Clamped so neither lobe is starved.
GI_FN float specular_lobe_probability(BrdfParams p, float NoV) {
  float s = luminance(F_Schlick(p.f0, NoV));
  float d = luminance(p.diffuse_color);
  if (d <= 0.0f) return 1.0f;
  if (s <= 0.0f) return 0.0f;
  return clamp(s / (s + d), 0.1f, 0.9f);
}

// Visible-normal sampling of GGX (Heitz 2018, "Sampling the GGX Distribution
// of Visible Normals"), v in the local frame (z = normal). Returns h.
GI_FN vec3 sample_ggx_vndf(vec3 v, float alpha, vec2 u) {
  vec3 vh = normalize(vec3(alpha * v.x, alpha * v.y, v.z));
  float lensq = vh.x * vh.x + vh.y * vh.y;
  vec3 t1 = lensq > 0.0f ? vec3(-vh.y, vh.x, 0.0f) * inversesqrt(lensq) : vec3(1.0f, 0.0f, 0.0f);
  vec3 t2 = cross(vh, t1);
  float r = sqrt(u.x);
  float phi = TWO_PI * u.y;
  float p1 = r * cos(phi);
  float p2 = r * sin(phi);
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * sqrt(max(0.0f, 1.0f - p1 * p1)) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return normalize(vec3(alpha * nh.x, alpha * nh.y, max(0.0f, nh.z)));
}

// pdf of l when l = reflect(-v, h) and h ~ VNDF: D(h) G1(v) / (4 NoV).
GI_FN float ggx_vndf_reflection_pdf(float alpha, float NoV, float NoH) {
  return D_GGX(alpha, NoH) * smith_G1(alpha, NoV) / (4.0f * NoV);
}

GI_FN float brdf_pdf(BrdfParams p, vec3 n, vec3 v, vec3 l) {
  float NoL = dot(n, l);
  if (NoL <= 0.0f) return 0.0f;
  float NoV = max(dot(n, v), BRDF_MIN_COS);
  float ps = specular_lobe_probability(p, NoV);
  vec3 h = normalize(v + l);
  float spec = ggx_vndf_reflection_pdf(p.alpha, NoV, saturate(dot(n, h)));
  return ps * spec + (1.0f - ps) * NoL * INV_PI;
}

// Samples l from the lobe mixture; returns false when the sample falls below
// the surface. pdf is the full mixture pdf (needed for MIS).
GI_FN bool brdf_sample(BrdfParams p, vec3 n, vec3 v, vec3 u, OUT(vec3) l, OUT(float) pdf) {
  float NoV = max(dot(n, v), BRDF_MIN_COS);
  float ps = specular_lobe_probability(p, NoV);
  if (u.z < ps) {
    vec3 vl = from_world(v, n);
    vl.z = max(vl.z, BRDF_MIN_COS);
    vec3 h = to_world(sample_ggx_vndf(normalize(vl), p.alpha, vec2(u.x, u.y)), n);
    l = reflect(-v, h);
  } else {
    l = to_world(sample_cosine_hemisphere(vec2(u.x, u.y)), n);
  }
  pdf = brdf_pdf(p, n, v, l);
  return pdf > 0.0f;
}

GI_SHADER_END

#endif
