// The material model both renderers shade with (docs/design.md §3, "Materials"):
// diffuse + GGX specular with Smith height-correlated visibility and Schlick
// Fresnel, F0 from base colour, metallic and reflectance (Filament / Bevy
// StandardMaterial conventions), roughness = perceptual². Which Bevy release's
// scene/brdf.wgsl it follows is the profile's `brdf.model`, carried by every
// material (GpuMaterial.reflectance.y) so both renderers shade alike:
//   BRDF_SINGLE_SCATTER      Lambert + single-scatter GGX (the harness's earlier model)
//   BRDF_MULTISCATTER_APPROX v0.17.0 / v0.18.0: the lobe × 1 + F0 (1/F_ab.x − 1) with
//                            Karis's polynomial F_ab (bevy_pbr pbr_lighting.wgsl:324-335, 523-529)
//   BRDF_LAYERED_POLYNOMIAL  between #23442 and #23737 (886ae0e5fa..5927c47b8d^): BRDF_LAYERED
//                            with Karis's polynomial F_ab, clamped ≥ 5e-5 (bevy_pbr #22833)
//   BRDF_LAYERED             v0.19.0 scene/brdf.wgsl:68-121: the diffuse lobe scaled by
//                            (1 − F(n·l)) (1 − F(n·v)), Fresnel with f90 = 1, the lobe
//                            × 1 + F0 (1/(F_ab.x + F_ab.y) − 1), F_ab from a DFG table (dfg_lut.h)
//   BRDF_LOBES_BLENDED_F0    #24243 (370be1b02f:scene/brdf.wgsl:24-33): the diffuse lobe is
//                            (1 − metallic)(1 − ρ_spec) base/π, ρ_spec the specular lobe's
//                            hemispherical reflectance from F_ab, for the blended F0
//   BRDF_LOBES               #24246 (4805ca792c:scene/brdf.wesl:24-34, 145-150): the metal and
//                            the dielectric lobe evaluated apart and mixed by metallic, the
//                            diffuse lobe from the dielectric's ρ_spec (Bevy main, 2026-08-22)
// Two flags ride above the model in the same word (#24668, NaN guards):
//   BRDF_FRESNEL_RAW    brdf.fresnel_argument "raw": Fresnel's cosine as computed, as
//                       0.19's fresnel(f0, LdotH) takes it (v0.19.0 scene/brdf.wgsl:114-116);
//                       a dot of unit vectors that rounds above 1 then gives
//                       pow(negative, 5): NaN on the GPU (std::pow in C++ stays finite)
//   BRDF_EVALUATE_CLAMP brdf.evaluate_clamp "max_zero": f = max(f, 0) (#24668,
//                       bde4e9d7c8:scene/brdf.wgsl:96), which on GPUs also turns NaN into 0
#ifndef GI_SHARED_BRDF_H
#define GI_SHARED_BRDF_H
#include "host_device.h"
#include "sampling.h"
#include "dfg_lut.h"

GI_SHADER_BEGIN

GI_CONST uint BRDF_SINGLE_SCATTER = 0u;
GI_CONST uint BRDF_MULTISCATTER_APPROX = 1u;
GI_CONST uint BRDF_LAYERED = 2u;
GI_CONST uint BRDF_LAYERED_POLYNOMIAL = 3u;
GI_CONST uint BRDF_LOBES_BLENDED_F0 = 4u;
GI_CONST uint BRDF_LOBES = 5u;
GI_CONST uint BRDF_MODEL_MASK = 15u;
GI_CONST uint BRDF_FRESNEL_RAW = 16u;
GI_CONST uint BRDF_EVALUATE_CLAMP = 32u;

// Every model from 0.19's on: Fresnel with f90 = 1, Filament's 1/(F_ab.x + F_ab.y).
GI_FN bool brdf_model_is_layered(uint model) { return model >= BRDF_LAYERED; }

// 0.18 clamps perceptual roughness to >= 0.0316 (roughness 0.001): below it
// D_GGX overflows in float and zero roughness gives NaN (Solari 0.18 post).
GI_CONST float MIN_PERCEPTUAL_ROUGHNESS = 0.0316f;

struct BrdfParams {
  vec3 diffuse_color;          // base_color * (1 - metallic)
  vec3 f0;                     // 0.16 reflectance² (1 - metallic) + base_color metallic
  vec3 f0_dielectric;          // 0.16 reflectance²: BRDF_LOBES's dielectric lobe
  vec3 f0_metal;               // base_color: BRDF_LOBES's metal lobe
  float metallic;
  float alpha;                 // perceptual_roughness², after the clamp
  float perceptual_roughness;  // after the clamp: F_ab's second coordinate
  uint model;                  // one of the BRDF_* models above
  uint flags;                  // BRDF_FRESNEL_RAW, BRDF_EVALUATE_CLAMP
};

// The clamp stays under every model. Bevy 0.19 drops it and treats α ≤ 0.001
// as an exact mirror instead (gbuffer_utils.wgsl:21, scene/brdf.wgsl:100-106);
// the clamped lobe has α = 0.001, which specular.h samples as that same exact
// reflection, so the two agree wherever a ray is reflected.
GI_FN BrdfParams brdf_params(vec3 base_color, float metallic, float perceptual_roughness, float reflectance,
                             uint model) {
  BrdfParams p;
  p.diffuse_color = base_color * (1.0f - metallic);
  p.f0_dielectric = vec3(0.16f * reflectance * reflectance);
  p.f0_metal = base_color;
  p.metallic = metallic;
  p.f0 = p.f0_dielectric * (1.0f - metallic) + base_color * metallic;
  float r = max(perceptual_roughness, MIN_PERCEPTUAL_ROUGHNESS);
  p.alpha = r * r;
  p.perceptual_roughness = r;
  p.model = model & BRDF_MODEL_MASK;
  p.flags = model & ~BRDF_MODEL_MASK;
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
// VoH comes saturated, or raw under BRDF_FRESNEL_RAW (fresnel_cos).
GI_FN vec3 F_Schlick(vec3 f0, float VoH) {
  float f90 = saturate(dot(f0, vec3(50.0f * 0.33f)));
  float f = pow(1.0f - VoH, 5.0f);
  return f0 + (vec3(f90) - f0) * f;
}

// Bevy 0.19's own Schlick (scene/brdf.wgsl:114-116): f90 = 1 for every f0.
GI_FN vec3 F_Schlick_f90_one(vec3 f0, float VoH) {
  return f0 + (vec3(1.0f) - f0) * pow(1.0f - VoH, 5.0f);
}

// Fresnel's cosine: saturated, or as computed (BRDF_FRESNEL_RAW, Bevy 0.19).
GI_FN float fresnel_cos(BrdfParams p, float c) { return (p.flags & BRDF_FRESNEL_RAW) != 0u ? c : saturate(c); }

GI_FN vec3 brdf_fresnel(BrdfParams p, float VoH) {
  return brdf_model_is_layered(p.model) ? F_Schlick_f90_one(p.f0, VoH) : F_Schlick(p.f0, VoH);
}

// Karis's polynomial fit of the split-sum scale and bias, as bevy_pbr has it
// in 0.17 and 0.18 (pbr_lighting.wgsl:523-529 at v0.18.0; no lower bound yet).
GI_FN vec2 F_ab_polynomial(float perceptual_roughness, float NoV) {
  vec4 c0 = vec4(-1.0f, -0.0275f, -0.572f, 0.022f);
  vec4 c1 = vec4(1.0f, 0.0425f, 1.04f, -0.04f);
  vec4 r = perceptual_roughness * c0 + c1;
  float a004 = min(r.x * r.x, exp2(-9.28f * NoV)) * r.x + r.y;
  return vec2(-1.04f, 1.04f) * a004 + vec2(r.z, r.w);
}

// F_ab under the material's model: the DFG table, or Karis's polynomial
// (clamped ≥ 5e-5 from bevy_pbr #22833 on, the state #23737 replaced).
GI_FN vec2 brdf_f_ab(BrdfParams p, float NoV) {
  if (p.model == BRDF_LAYERED_POLYNOMIAL) return max(F_ab_polynomial(p.perceptual_roughness, NoV), vec2(5e-5f));
  return dfg_lut_f_ab(NoV, p.perceptual_roughness);
}

// bevy_pbr's multiscatter factor (specular_multiscatter) for one F0; 1 under
// the single-scatter model. 0.17 and 0.18 divide by the scale alone,
// 1 + F0 (1/F_ab.x − 1) (v0.18.0 pbr_lighting.wgsl:324-335), so a rough
// white metal reflects more than it receives; from 0.19 on it divides by the
// single-scatter albedo F_ab.x + F_ab.y as Filament does (v0.19.0
// pbr_lighting.wgsl:330-342, #23514).
GI_FN vec3 energy_compensation_for(BrdfParams p, vec3 f0, float NoV) {
  if (p.model == BRDF_SINGLE_SCATTER) return vec3(1.0f);
  if (brdf_model_is_layered(p.model)) {
    vec2 f_ab = brdf_f_ab(p, NoV);
    return vec3(1.0f) + f0 * (1.0f / (f_ab.x + f_ab.y) - 1.0f);
  }
  vec2 f_ab = F_ab_polynomial(p.perceptual_roughness, NoV);
  return vec3(1.0f) + f0 * (1.0f / f_ab.x - 1.0f);
}

GI_FN vec3 energy_compensation(BrdfParams p, float NoV) { return energy_compensation_for(p, p.f0, NoV); }

// Hemispherical reflectance of the compensated specular lobe for one F0
// (Bevy's lobe_reflectances, 370be1b02f:scene/brdf.wgsl:24-33).
GI_FN vec3 specular_reflectance(BrdfParams p, vec3 f0, float NoV) {
  vec2 f_ab = brdf_f_ab(p, NoV);
  return (f0 * f_ab.x + vec3(f_ab.y)) * energy_compensation_for(p, f0, NoV);
}

// Cosines below this count as grazing; keeps every division finite.
GI_CONST float BRDF_MIN_COS = 1e-6f;

// The specular lobe under the material's model: D · V · F, times the
// multiscatter factor (Bevy: evaluate_specular_brdf, without the cosine),
// n facing v. No clamp here: alpha = 0 at the mirror direction is
// D_GGX = 0/0.
GI_FN vec3 specular_lobe(BrdfParams p, vec3 n, vec3 v, vec3 l) {
  float NoL = dot(n, l);
  if (NoL <= 0.0f) return vec3(0.0f);
  float NoV = max(dot(n, v), BRDF_MIN_COS);
  vec3 h = normalize(v + l);
  float NoH = saturate(dot(n, h));
  float VoH = fresnel_cos(p, dot(v, h));
  float dv = D_GGX(p.alpha, NoH) * V_SmithGGXCorrelated(p.alpha, NoV, NoL);
  if (p.model == BRDF_LOBES) {
    // #24246: each lobe with its own Fresnel and multiscatter factor.
    vec3 dielectric = F_Schlick_f90_one(p.f0_dielectric, VoH) * energy_compensation_for(p, p.f0_dielectric, NoV);
    vec3 metal = F_Schlick_f90_one(p.f0_metal, VoH) * energy_compensation_for(p, p.f0_metal, NoV);
    return dv * mix(dielectric, metal, p.metallic);
  }
  return dv * brdf_fresnel(p, VoH) * energy_compensation(p, NoV);
}

// The diffuse lobe alone (Bevy: evaluate_diffuse_brdf, without the cosine).
// v matters only under the layered models: 0.19's lobe is what the two
// Fresnel transmissions leave (scene/brdf.wgsl:89-99 at v0.19.0: zero below
// 1e-4), main's what the specular lobe does not reflect.
GI_FN vec3 brdf_eval_diffuse(BrdfParams p, vec3 n, vec3 v, vec3 l) {
  float NoL = dot(n, l);
  if (!brdf_model_is_layered(p.model)) return NoL > 0.0f ? p.diffuse_color * INV_PI : vec3(0.0f);
  float NoV = dot(n, v);
  if (NoL < 0.0001f || NoV < 0.0001f) return vec3(0.0f);
  // #24243 on: what the specular lobe does not reflect, for all l alike.
  if (p.model == BRDF_LOBES_BLENDED_F0) return p.diffuse_color * INV_PI * (vec3(1.0f) - specular_reflectance(p, p.f0, NoV));
  if (p.model == BRDF_LOBES)
    return p.diffuse_color * INV_PI * (vec3(1.0f) - specular_reflectance(p, p.f0_dielectric, NoV));
  vec3 layering = (vec3(1.0f) - F_Schlick_f90_one(p.f0, fresnel_cos(p, NoL))) *
                   (vec3(1.0f) - F_Schlick_f90_one(p.f0, fresnel_cos(p, NoV)));
  return p.diffuse_color * INV_PI * layering;
}

// Whether the specular lobe can reflect anything: F0 > 0, or Fresnel's
// grazing reflection under 0.19's f90 = 1 (then even reflectance 0 reflects).
GI_FN bool brdf_has_specular(BrdfParams p) { return brdf_model_is_layered(p.model) || max3(p.f0) > 0.0f; }

// f(v, l) (without the cosine), n the shading normal facing v.
GI_FN vec3 brdf_eval(BrdfParams p, vec3 n, vec3 v, vec3 l) {
  if (dot(n, l) <= 0.0f) return vec3(0.0f);
  vec3 f = brdf_eval_diffuse(p, n, v, l) + specular_lobe(p, n, v, l);
  // GLSL's max returns the number when one side is NaN on every GPU we run
  // (lavapipe's fmax, NVIDIA's); glm's keeps the NaN, but C++ makes none here.
  return (p.flags & BRDF_EVALUATE_CLAMP) != 0u ? max(f, vec3(0.0f)) : f;
}

// Probability of sampling the specular lobe; depends on v only, so sampling
// and pdf evaluation agree. Clamped so neither lobe is starved.
GI_FN float specular_lobe_probability(BrdfParams p, float NoV) {
  float s = luminance(brdf_fresnel(p, saturate(NoV)));  // the harness's own: always saturated
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
