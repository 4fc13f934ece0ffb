// Specular GI's maths (DESIGN §3 step 8), shared by gpu/shaders/specular_gi.comp
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
GI_FN vec3 specular_sample_weight(BrdfParams p, vec3 n, vec3 v, vec3 l) {
  vec3 vl = from_world(v, n);
  vec3 ll = from_world(l, n);
  float pdf = ggx_bounded_vndf_pdf(vl, ll, p.alpha);
  return specular_lobe(p, n, v, l) * max(dot(n, l), 0.0f) / pdf;
}

GI_SHADER_END

#endif
