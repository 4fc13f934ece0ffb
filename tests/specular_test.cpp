// CPU tests of core/shared/specular.h, the code specular_gi.comp runs:
// bounded-VNDF sampling agrees with its pdf, the mirror special case, the
// NaN that zero roughness gives without the profile's clamp, and Solari
// 0.18's bounce in the mesh-tangent frame (#23948).
#include <gtest/gtest.h>

#include <cmath>

#include "core/shared/rng.h"
#include "core/shared/specular.h"

namespace {

using namespace gi::shader;

vec3 view_at(float theta) { return vec3(std::sin(theta), 0.0f, std::cos(theta)); }

// E[g(l)/pdf(l)] over the sampler = ∫ g over where it samples: with g = 1 on
// the upper hemisphere that is 2π when the sampler covers it and its pdf is right.
TEST(BoundedVndf, SamplesAgreeWithThePdf) {
  for (float alpha : {0.05f, 0.3f, 0.8f})
    for (float theta : {0.1f, 0.8f, 1.4f}) {
      const vec3 v = view_at(theta);
      std::uint32_t rng = 12345u;
      double sum = 0, sum2 = 0;
      const int n = 200000;
      for (int i = 0; i < n; ++i) {
        const vec3 l = sample_ggx_bounded_vndf(v, alpha, rng_next_vec2(rng));
        double x = 0;
        if (l.z > 0.0f) x = 1.0 / ggx_bounded_vndf_pdf(v, l, alpha);
        sum += x;
        sum2 += x * x;
      }
      const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
      // A narrow lobe at grazing view leaves part of the hemisphere almost
      // unsampled, so only an upper bound holds there; otherwise 2π ± 5 se.
      EXPECT_LT(mean, 2.0 * PI + 5 * se + 1e-3) << alpha << " " << theta;
      if (alpha >= 0.3f) EXPECT_NEAR(mean, 2.0 * PI, 5 * se + 0.02 * 2 * PI) << alpha << " " << theta;
    }
}

TEST(BoundedVndf, MirrorSpecialCaseReflectsExactly) {
  const vec3 v = normalize(vec3(0.3f, -0.2f, 0.9f));
  for (float alpha : {0.0f, 1e-4f, 0.001f}) {
    const vec3 l = sample_ggx_bounded_vndf(v, alpha, vec2(0.37f, 0.81f));
    EXPECT_FLOAT_EQ(l.x, -v.x);
    EXPECT_FLOAT_EQ(l.y, -v.y);
    EXPECT_FLOAT_EQ(l.z, v.z);
  }
  EXPECT_NE(sample_ggx_bounded_vndf(v, 0.002f, vec2(0.37f, 0.81f)).x, -v.x);
}

// A specular-only material with the given F0 and alpha under a model.
BrdfParams lobe(vec3 f0, float alpha, uint model = BRDF_SINGLE_SCATTER) {
  BrdfParams p = brdf_params(vec3(0.0f), 0.0f, 1.0f, 0.0f, model);
  p.f0 = f0;
  p.alpha = alpha;
  p.perceptual_roughness = std::sqrt(alpha);
  return p;
}

// The clamp (brdf.min_perceptual_roughness = 0.0316) keeps the weight finite
// and close to F at the mirror; without it zero roughness is 0/0.
TEST(SpecularWeight, FiniteWithTheClampNaNWithoutIt) {
  const vec3 n(0, 0, 1), f0(0.9f, 0.8f, 0.7f);
  for (float theta : {0.0f, 0.5f, 1.2f, 1.55f}) {
    const vec3 v = view_at(theta);
    const vec3 l = vec3(-v.x, -v.y, v.z);
    const float clamped = specular_alpha(0.0f, 0.0316f);
    const vec3 w = specular_sample_weight(lobe(f0, clamped), n, v, l);
    const vec3 f = F_Schlick(f0, v.z);
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(w[c])) << theta;
      EXPECT_NEAR(w[c], f[c], 0.1f * f[c]) << theta;
    }
    const vec3 unclamped = specular_sample_weight(lobe(f0, specular_alpha(0.0f, 0.0f)), n, v, l);
    EXPECT_TRUE(std::isnan(unclamped.x)) << theta;
  }
}

// The specular lobe's directional albedo (F = 1) estimated by bounded-VNDF
// sampling equals the one by uniform hemisphere sampling under every material
// model: the estimator specular_gi.comp forms (brdf·cos/pdf) is unbiased, and
// at most 1 under the single-scatter model (0.17/0.18's compensation exceeds
// it, dfg_lut_test.cpp).
TEST(SpecularWeight, BoundedVndfEstimatorAgreesWithUniformSampling) {
  const vec3 n(0, 0, 1), f0(1.0f);
  for (uint model : {BRDF_SINGLE_SCATTER, BRDF_MULTISCATTER_APPROX, BRDF_LAYERED})
  for (float alpha : {0.05f, 0.2f, 0.6f})
    for (float theta : {0.3f, 1.1f}) {
      const vec3 v = view_at(theta);
      std::uint32_t rng = 99u;
      double vndf = 0, uniform = 0, uniform2 = 0;
      const int count = 200000;
      for (int i = 0; i < count; ++i) {
        const vec3 l = sample_ggx_bounded_vndf(v, alpha, rng_next_vec2(rng));
        if (l.z > 0.0f) vndf += specular_sample_weight(lobe(f0, alpha, model), n, v, l).x;
        const vec3 u = sample_uniform_hemisphere(rng_next_vec2(rng));
        const double x = specular_lobe(lobe(f0, alpha, model), n, v, u).x * u.z * TWO_PI;
        uniform += x;
        uniform2 += x * x;
      }
      vndf /= count;
      uniform /= count;
      const double se = std::sqrt((uniform2 / count - uniform * uniform) / count);
      EXPECT_NEAR(vndf, uniform, 5 * se + 2e-3) << model << " " << alpha << " " << theta;
      if (model == BRDF_SINGLE_SCATTER) EXPECT_LE(vndf, 1.005) << alpha << " " << theta;
    }
}

// Solari 0.18's bounce in the mesh frame (brdf.sampling_frame mikktspace):
// with a tangent perpendicular to the normal the frame is orthonormal and the
// estimator is the unbiased one; where a normal map has leaned the normal
// towards the tangent (T·N = 0.5) the skewed frame biases it (#23948).
TEST(SpecularWeight, MeshFrameIsUnbiasedOnlyWhenTheTangentIsPerpendicular) {
  const vec3 n(0, 0, 1), f0(1.0f);
  const float alpha = 0.09f;
  const BrdfParams p = lobe(f0, alpha, BRDF_SINGLE_SCATTER);
  for (float theta : {0.3f, 0.9f}) {
    const vec3 v = view_at(theta);
    auto estimate = [&](vec4 tangent, double& se) {
      std::uint32_t rng = 7u;
      double sum = 0, sum2 = 0;
      const int count = 200000;
      for (int i = 0; i < count; ++i) {
        vec3 l;
        float pdf;
        double x = 0;
        if (sample_specular_in_mesh_frame(p, n, tangent, v, rng_next_vec2(rng), l, pdf))
          x = brdf_eval(p, n, v, l).x * std::max(dot(n, l), 0.0f) / pdf;
        sum += x;
        sum2 += x * x;
      }
      const double mean = sum / count;
      se = std::sqrt((sum2 / count - mean * mean) / count);
      return mean;
    };
    double se_a = 0, se_b = 0, se_c = 0;
    const double reference = estimate(vec4(0.0f, 1.0f, 0.0f, 1.0f), se_a);  // orthonormal, rotated
    const double rotated = estimate(vec4(normalize(vec3(1.0f, 1.0f, 0.0f)), -1.0f), se_b);
    EXPECT_NEAR(rotated, reference, 5 * (se_a + se_b) + 2e-3) << theta;
    const double skewed = estimate(vec4(normalize(vec3(std::sqrt(3.0f), 0.0f, 1.0f)), 1.0f), se_c);  // T·N = 0.5
    EXPECT_GT(std::abs(skewed - reference), std::max(0.05 * reference, 10 * (se_a + se_c))) << theta;
  }
}

// Solari's glossy-path MIS before #24671 (specular.mis_light_pdf area) only
// swaps which pdf the light side brings; the flag must not change the heuristic.
TEST(MisWeight, LightPdfInAreaFlagKeepsTheHeuristic) {
  EXPECT_FLOAT_EQ(mis_weight(MIS_POWER | MIS_LIGHT_PDF_AREA, 2.0f, 3.0f), power_heuristic(2.0f, 3.0f));
  EXPECT_FLOAT_EQ(mis_weight(MIS_BALANCE | MIS_LIGHT_PDF_AREA, 2.0f, 3.0f), balance_heuristic(2.0f, 3.0f));
}

}  // namespace
