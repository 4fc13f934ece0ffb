// Specular GI's maths (docs/design.md §3 step 8), shared by gpu/shaders/specular_gi.comp
// and tests/specular_test.cpp (host_device.h rules): GGX reflection sampling
// with bounded VNDF (Eto & Tokuyoshi, "Bounded VNDF Sampling for Smith-GGX
// Reflections", SIGGRAPH Asia 2023, listings 1 and 2) and its pdf, the mirror
// special case, and the specular lobe of brdf.h evaluated at a roughness the
// caller clamps (or not: the 0.17 profile's zero roughness gives NaN, which is
// what the `finite` check must see).
#ifndef GI_SHARED_SPECULAR_H
#define GI_SHARED_SPECULAR_H
#include "host_device.h"
#include "brdf.h"

GI_SHADER_BEGIN

// At or below this alpha sampling returns the reflection of v exactly
// (Solari 0.18's mirror special case, seeds/solari-0.18.md: "roughness <= 0.001"):
// the clamped profile's smoothest lobe (alpha 0.001) renders as a mirror while
// its BRDF and pdf stay finite.
GI_CONST float SPECULAR_MIRROR_ALPHA = 0.001f;

// The profile's clamp (brdf.min_perceptual_roughness; 0 = off) applied to a
// perceptual roughness; returns alpha = perceptual².
GI_FN float specular_alpha(float perceptual_roughness, float min_perceptual_roughness) {
  float r = max(perceptual_roughness, min_perceptual_roughness);
  return r * r;
}

// Sampling's own mirror shortcut. Solari's sample_ggx_vndf tests 0.001 in
// every release (v0.18.0:scene/sampling.wgsl:22); between #21907 and #22240
// it tested 0.01 (6458934142^:scene/sampling.wgsl:21-24), so lobes of alpha
// up to 0.01 rendered as mirrors, with GGX's own weight. The realtime passes
// define it from specular.vndf_mirror_alpha when that is not 0.001.
#ifndef SPECULAR_MIRROR_EXACT
#define SPECULAR_MIRROR_EXACT 0
#endif
#ifndef SPECULAR_VNDF_MIRROR_ALPHA
#define SPECULAR_VNDF_MIRROR_ALPHA SPECULAR_MIRROR_ALPHA
#endif

// v (towards the viewer) and the result in the local frame, z = normal.
// Returns the reflected direction l.
GI_FN vec3 sample_ggx_bounded_vndf(vec3 v, float alpha, vec2 u) {
  if (alpha <= SPECULAR_VNDF_MIRROR_ALPHA) return vec3(-v.x, -v.y, v.z);
  vec3 v_std = normalize(vec3(v.x * alpha, v.y * alpha, v.z));
  float phi = TWO_PI * u.x;
  float a = saturate(alpha);
  float s = 1.0f + length(vec2(v.x, v.y));
  float a2 = a * a;
  float s2 = s * s;
  float k = (1.0f - a2) * s2 / (s2 + a2 * v.z * v.z);
  float b = v.z > 0.0f ? k * v_std.z : v_std.z;
  float z = (1.0f - u.y) * (1.0f + b) - b;
  float sin_theta = sqrt(saturate(1.0f - z * z));
  vec3 o_std = vec3(sin_theta * cos(phi), sin_theta * sin(phi), z);
  vec3 m_std = v_std + o_std;
  vec3 m = normalize(vec3(m_std.x * alpha, m_std.y * alpha, m_std.z));
  return 2.0f * dot(v, m) * m - v;
}

// Solid-angle pdf of l under sample_ggx_bounded_vndf (local frame), for
// alpha > 0. For the mirror special case it is used as Solari uses it: brdf
// and pdf share D_GGX, so their ratio is still right at alpha 0.001; at
// alpha 0 (no clamp) D_GGX(0, 1) = 0/0 and the ratio is NaN.
GI_FN float ggx_bounded_vndf_pdf(vec3 v, vec3 l, float alpha) {
  vec3 m = normalize(v + l);
  float ndf = D_GGX(alpha, saturate(m.z));
  vec2 ai = alpha * vec2(v.x, v.y);
  float len2 = dot(ai, ai);
  float t = sqrt(len2 + v.z * v.z);
  if (v.z >= 0.0f) {
    float a = saturate(alpha);
    float s = 1.0f + length(vec2(v.x, v.y));
    float a2 = a * a;
    float s2 = s * s;
    float k = (1.0f - a2) * s2 / (s2 + a2 * v.z * v.z);
    return ndf / (2.0f * (k * v.z + t));
  }
  return ndf * (t - v.z) / (2.0f * len2);
}

// brdf · cos / pdf of a direction drawn by sample_ggx_bounded_vndf, formed
// the way Solari forms it (brdf and pdf apart): ≈ F at the clamped mirror,
// NaN at alpha 0 — the bug the `finite` check exists for. The lobe is the
// material model's (specular_lobe) at p.alpha, which the caller may have
// set from its own clamp.
//
// SPECULAR_MIRROR_EXACT (brdf.mirror "exact", Solari 0.19 after #22468,
// v0.19.0:scene/brdf.wgsl:100-106 with the mirror pdf of
// scene/sampling.wgsl:55-60): at or below SPECULAR_MIRROR_ALPHA the sampled
// reflection carries the Fresnel term alone. Otherwise ("clamped_ggx", 0.18)
// the alpha-0.001 lobe's D at a world-space half vector is divided by the
// pdf's D at the local one: equal on a mirror that lies along the axes, off
// by float rounding on a tilted one, where reflections darken in patches.
GI_FN vec3 specular_sample_weight(BrdfParams p, vec3 n, vec3 v, vec3 l) {
#if SPECULAR_MIRROR_EXACT
  if (p.alpha <= SPECULAR_MIRROR_ALPHA) {
    float NoV = fresnel_cos(p, dot(n, v));
    if (p.model == BRDF_LOBES)
      return mix(F_Schlick_f90_one(p.f0_dielectric, NoV), F_Schlick_f90_one(p.f0_metal, NoV), p.metallic);
    return brdf_fresnel(p, NoV);
  }
#endif
  vec3 vl = from_world(v, n);
  vec3 ll = from_world(l, n);
  float pdf = ggx_bounded_vndf_pdf(vl, ll, p.alpha);
  return specular_lobe(p, n, v, l) * max(dot(n, l), 0.0f) / pdf;
}

// Solari 0.18's bounce at a glossy path's hit (v0.18.0:realtime/specular_gi.wgsl:96,
// 128-136; fixed by #23948): the frame is bevy_pbr's calculate_tbn_mikktspace,
// (T, w·cross(N, T), N) from the mesh tangent and the mapped normal with no
// Gram-Schmidt, so where a normal map tilts N towards T it is skewed. v is
// projected on it, GGX's bounded VNDF sampled there and its pdf taken there,
// and the sample mapped back unnormalised (the caller evaluates the BRDF at
// that vector, as Bevy does, and normalises it to trace). No Jacobian of the
// skew: the estimate is biased, and a mirror's reflection misses its lobe.
GI_FN bool sample_specular_in_mesh_frame(BrdfParams p, vec3 n, vec4 tangent, vec3 v, vec2 u, OUT(vec3) l,
                                         OUT(float) pdf) {
  vec3 t = vec3(tangent);
  vec3 b = tangent.w * cross(n, t);
  vec3 vt = vec3(dot(v, t), dot(v, b), dot(v, n));
  vec3 lt = sample_ggx_bounded_vndf(vt, p.alpha, u);
  l = lt.x * t + lt.y * b + lt.z * n;
  pdf = ggx_bounded_vndf_pdf(vt, lt, p.alpha);
  return pdf > 0.0f && dot(l, l) > 0.0f;
}

GI_SHADER_END

#endif
