// CPU tests of the maths the GPU shaders run (core/shared/*.h compiles as GLSL
// and as C++): random numbers, sampling routines against their pdfs, and the
// BRDF. Every statistical test uses a fixed seed (deterministic) and states
// its threshold; thresholds are ≥ 5 standard errors or a chi-square p-value
// around 1e-6, so a correct implementation never comes close.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"

namespace {

using namespace gi::shader;

// Pearson chi-square statistic of counts against expected probabilities.
double chi_square(const std::vector<double>& counts, const std::vector<double>& probs) {
  double n = 0;
  for (double c : counts) n += c;
  double chi2 = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const double e = n * probs[i];
    chi2 += (counts[i] - e) * (counts[i] - e) / e;
  }
  return chi2;
}

// Upper chi-square threshold for k degrees of freedom at p ≈ 1e-6 (Wilson–
// Hilferty: mean k, z = 4.75).
double chi_square_limit(int k) {
  const double z = 4.75, a = 2.0 / (9.0 * k);
  const double t = 1.0 - a + z * std::sqrt(a);
  return k * t * t * t;
}

struct Stream {
  uint state;
  explicit Stream(uint seed) : state(rng_seed(seed, RNG_DOMAIN_EMBREE, 12345u, 0u)) {}
  float next() { return rng_next_float(state); }
  vec2 next2() { return rng_next_vec2(state); }
};

struct MeanEstimate {
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  void add(double v) { sum += v, sum2 += v * v, ++n; }
  double mean() const { return sum / double(n); }
  double standard_error() const {
    const double m = mean();
    return std::sqrt(std::max(0.0, sum2 / double(n) - m * m) / double(n));
  }
};

TEST(SharedRng, FloatInUnitIntervalAndUniform) {
  constexpr int kBins = 64;
  constexpr int kDraws = 1000000;
  std::vector<double> counts(kBins, 0.0);
  Stream s(7);
  for (int i = 0; i < kDraws; ++i) {
    const float u = s.next();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    counts[std::min(int(u * kBins), kBins - 1)] += 1;
  }
  // 63 degrees of freedom: limit ≈ 124 (p ≈ 1e-6).
  EXPECT_LT(chi_square(counts, std::vector<double>(kBins, 1.0 / kBins)), chi_square_limit(kBins - 1));
}

// The first draw of each pixel's seeded state must be uniform too: that is the
// number every path starts with.
TEST(SharedRng, FirstDrawAcrossPixelsIsUniform) {
  constexpr int kBins = 64;
  std::vector<double> counts(kBins, 0.0);
  for (uint pixel = 0; pixel < 1000000u; ++pixel) {
    uint state = rng_seed(1u, RNG_DOMAIN_EMBREE, pixel, 0u);
    counts[std::min(int(rng_next_float(state) * kBins), kBins - 1)] += 1;
  }
  EXPECT_LT(chi_square(counts, std::vector<double>(kBins, 1.0 / kBins)), chi_square_limit(kBins - 1));
}

TEST(SharedRng, DomainsGiveDifferentStreams) {
  int same = 0;
  for (uint p = 0; p < 1000u; ++p)
    same += rng_seed(1u, RNG_DOMAIN_EMBREE, p, 0u) == rng_seed(1u, RNG_DOMAIN_GPU_REFERENCE, p, 0u);
  EXPECT_EQ(same, 0);
}

// Histogram of cos(theta) in 32 bins against the CDF each sampler promises.
template <class Sampler, class Cdf>
void expect_cos_theta_distribution(Sampler sample, Cdf cdf, float cos_min) {
  constexpr int kBins = 32;
  constexpr int kDraws = 400000;
  std::vector<double> counts(kBins, 0.0), probs(kBins);
  for (int b = 0; b < kBins; ++b) {
    const double lo = cos_min + (1.0 - cos_min) * b / kBins, hi = cos_min + (1.0 - cos_min) * (b + 1) / kBins;
    probs[b] = cdf(hi) - cdf(lo);
  }
  Stream s(3);
  for (int i = 0; i < kDraws; ++i) {
    const vec3 d = sample(s.next2());
    ASSERT_NEAR(length(d), 1.0f, 1e-5f);
    ASSERT_GE(d.z, cos_min - 1e-6f);
    const int b = std::clamp(int((d.z - cos_min) / (1.0f - cos_min) * kBins), 0, kBins - 1);
    counts[b] += 1;
  }
  EXPECT_LT(chi_square(counts, probs), chi_square_limit(kBins - 1));
}

// E[f] over the sampler against the analytic value; tolerance 5 standard errors.
template <class Sampler, class F>
void expect_mean(Sampler sample, F f, double expected) {
  Stream s(11);
  MeanEstimate m;
  for (int i = 0; i < 200000; ++i) m.add(f(sample(s.next2())));
  EXPECT_NEAR(m.mean(), expected, 5.0 * m.standard_error() + 1e-6);
}

TEST(SharedSampling, CosineHemisphereMatchesPdf) {
  // pdf cos/pi: P(cos θ ≤ c) = c²; E[cos θ] = 2/3; E[x] = E[y] = 0.
  expect_cos_theta_distribution(sample_cosine_hemisphere, [](double c) { return c * c; }, 0.0f);
  expect_mean(sample_cosine_hemisphere, [](vec3 d) { return double(d.z); }, 2.0 / 3.0);
  expect_mean(sample_cosine_hemisphere, [](vec3 d) { return double(d.x); }, 0.0);
  expect_mean(sample_cosine_hemisphere, [](vec3 d) { return double(d.y); }, 0.0);
}

TEST(SharedSampling, UniformHemisphereMatchesPdf) {
  // pdf 1/(2 pi): cos θ uniform on [0, 1]; E[cos θ] = 1/2, E[cos² θ] = 1/3.
  expect_cos_theta_distribution(sample_uniform_hemisphere, [](double c) { return c; }, 0.0f);
  expect_mean(sample_uniform_hemisphere, [](vec3 d) { return double(d.z); }, 0.5);
  expect_mean(sample_uniform_hemisphere, [](vec3 d) { return double(d.z) * d.z; }, 1.0 / 3.0);
  expect_mean(sample_uniform_hemisphere, [](vec3 d) { return double(d.x); }, 0.0);
}

TEST(SharedSampling, ConeMatchesPdf) {
  for (float theta_max : {0.6f, 0.1f, 0.00465f}) {
    const float omc = one_minus_cos(theta_max);
    const double cmin = std::cos(double(theta_max));
    EXPECT_NEAR(omc, 1.0 - cmin, 1e-6 * (1.0 - cmin) + 1e-12);
    auto sampler = [omc](vec2 u) { return sample_cone(u, omc); };
    // Uniform in the cone: cos θ uniform on [cos θmax, 1]; E[cos θ] = (1 + cos θmax)/2.
    // (The histogram is skipped for the sun-sized cone: float cos θ cannot resolve it.)
    if (theta_max > 0.05f)
      expect_cos_theta_distribution(sampler, [cmin](double c) { return (c - cmin) / (1.0 - cmin); }, float(cmin));
    expect_mean(sampler, [](vec3 d) { return 1.0 - double(d.z); }, 0.5 * (1.0 - cmin));
    Stream s(5);
    for (int i = 0; i < 10000; ++i) ASSERT_LE(std::acos(std::min(1.0f, sample_cone(s.next2(), omc).z)), theta_max * 1.001f + 1e-3f);
    EXPECT_NEAR(cone_solid_angle(omc), 2.0 * M_PI * (1.0 - cmin), 1e-5 * (1.0 - cmin));
  }
}

TEST(SharedSampling, TriangleIsUniform) {
  const vec3 p0(0.0f, 0.0f, 0.0f), p1(3.0f, 0.0f, 0.0f), p2(1.0f, 2.0f, 0.0f);
  Stream s(13);
  MeanEstimate mx, my;
  // The four midpoint sub-triangles each hold a quarter of the area.
  std::vector<double> counts(4, 0.0);
  for (int i = 0; i < 400000; ++i) {
    const vec2 b = sample_triangle(s.next2());
    ASSERT_GE(b.x, 0.0f);
    ASSERT_GE(b.y, 0.0f);
    ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
    const vec3 p = (1.0f - b.x - b.y) * p0 + b.x * p1 + b.y * p2;
    mx.add(p.x), my.add(p.y);
    const float b0 = 1.0f - b.x - b.y;
    counts[b0 > 0.5f ? 0 : b.x > 0.5f ? 1 : b.y > 0.5f ? 2 : 3] += 1;
  }
  const vec3 centroid = (p0 + p1 + p2) / 3.0f;
  EXPECT_NEAR(mx.mean(), centroid.x, 5.0 * mx.standard_error());
  EXPECT_NEAR(my.mean(), centroid.y, 5.0 * my.standard_error());
  EXPECT_LT(chi_square(counts, {0.25, 0.25, 0.25, 0.25}), chi_square_limit(3));
}

TEST(SharedSampling, OrthonormalBasis) {
  Stream s(17);
  for (int i = 0; i < 10000; ++i) {
    vec2 u = s.next2();
    vec3 n = sample_uniform_hemisphere(u);
    if (i & 1) n = -n;
    vec3 t, b;
    orthonormal_basis(n, t, b);
    ASSERT_NEAR(dot(t, b), 0.0f, 1e-5f);
    ASSERT_NEAR(dot(t, n), 0.0f, 1e-5f);
    ASSERT_NEAR(length(t), 1.0f, 1e-5f);
    const vec3 w = normalize(vec3(0.3f, -0.5f, 0.8f));
    const vec3 back = to_world(from_world(w, n), n);
    ASSERT_NEAR(length(back - w), 0.0f, 1e-5f);
  }
}

struct BrdfCase {
  float roughness, metallic, NoV;
};

// The cases every statistical BRDF test runs: dielectric and metal, rough to
// fairly glossy, head-on to grazing views.
const BrdfCase kCases[] = {{1.0f, 0.0f, 0.9f}, {0.5f, 0.0f, 0.7f}, {0.3f, 1.0f, 0.5f},
                           {0.8f, 0.5f, 0.2f}, {0.25f, 0.0f, 0.95f}, {0.6f, 1.0f, 0.05f}};

vec3 view_with(float NoV) { return vec3(std::sqrt(1.0f - NoV * NoV), 0.0f, NoV); }

TEST(SharedBrdf, SampleReturnsItsPdf) {
  const vec3 n(0.0f, 0.0f, 1.0f);
  for (const BrdfCase& c : kCases) {
    const BrdfParams p = brdf_params(vec3(0.8f, 0.6f, 0.4f), c.metallic, c.roughness, 0.5f, BRDF_SINGLE_SCATTER);
    const vec3 v = view_with(c.NoV);
    Stream s(19);
    for (int i = 0; i < 20000; ++i) {
      const vec3 u(s.next(), s.next(), s.next());
      vec3 l;
      float pdf;
      if (!brdf_sample(p, n, v, u, l, pdf)) continue;
      ASSERT_GT(pdf, 0.0f);
      ASSERT_GT(dot(n, l), 0.0f);
      ASSERT_EQ(pdf, brdf_pdf(p, n, v, l));  // same function, bit for bit
    }
  }
}

// The directions brdf_sample draws really have density brdf_pdf: then
// E[g(l)/pdf(l)] over its valid samples is ∫ g over the upper hemisphere, for
// any g. Checked for g = cos θ (∫ = pi) and g = cos θ inside a 25° cone
// around the mirror direction (∫ by uniform-hemisphere Monte Carlo).
// Tolerance: 5 combined standard errors.
TEST(SharedBrdf, SampledDirectionsFollowPdf) {
  const vec3 n(0.0f, 0.0f, 1.0f);
  constexpr int kDraws = 400000;
  for (const BrdfCase& c : kCases) {
    SCOPED_TRACE(::testing::Message() << "roughness " << c.roughness << " metallic " << c.metallic << " NoV " << c.NoV);
    const BrdfParams p = brdf_params(vec3(0.8f, 0.6f, 0.4f), c.metallic, c.roughness, 0.5f, BRDF_SINGLE_SCATTER);
    const vec3 v = view_with(c.NoV);
    const vec3 mirror = reflect(-v, n);
    const float cos_cone = std::cos(25.0f * PI / 180.0f);
    auto g_cone = [&](vec3 l) { return dot(l, mirror) > cos_cone ? double(l.z) : 0.0; };
    MeanEstimate all, cone;
    Stream s(23);
    for (int i = 0; i < kDraws; ++i) {
      const vec3 u(s.next(), s.next(), s.next());
      vec3 l;
      float pdf;
      if (!brdf_sample(p, n, v, u, l, pdf)) {
        all.add(0), cone.add(0);
        continue;
      }
      all.add(double(l.z) / pdf);
      cone.add(g_cone(l) / pdf);
    }
    EXPECT_NEAR(all.mean(), PI, 5.0 * all.standard_error());
    EXPECT_LT(all.standard_error(), 0.01 * PI);  // the test has power
    MeanEstimate truth;
    Stream t(29);
    for (int i = 0; i < kDraws; ++i) truth.add(g_cone(sample_uniform_hemisphere(t.next2())) * TWO_PI);
    const double se = std::hypot(cone.standard_error(), truth.standard_error());
    EXPECT_NEAR(cone.mean(), truth.mean(), 5.0 * se);
  }
}

// ∫ pdf dω over the upper hemisphere (uniform-hemisphere Monte Carlo) is the
// probability that brdf_sample returns a direction: ≤ 1, and equal to the
// fraction of successful samples. Tolerance 5 standard errors.
TEST(SharedBrdf, PdfIntegratesToAtMostOne) {
  const vec3 n(0.0f, 0.0f, 1.0f);
  constexpr int kDraws = 1000000;
  for (const BrdfCase& c : kCases) {
    SCOPED_TRACE(::testing::Message() << "roughness " << c.roughness << " metallic " << c.metallic << " NoV " << c.NoV);
    const BrdfParams p = brdf_params(vec3(0.8f, 0.6f, 0.4f), c.metallic, c.roughness, 0.5f, BRDF_SINGLE_SCATTER);
    const vec3 v = view_with(c.NoV);
    MeanEstimate integral;
    Stream s(31);
    for (int i = 0; i < kDraws; ++i) integral.add(double(brdf_pdf(p, n, v, sample_uniform_hemisphere(s.next2()))) * TWO_PI);
    double valid = 0;
    Stream t(37);
    for (int i = 0; i < kDraws; ++i) {
      vec3 l;
      float pdf;
      valid += brdf_sample(p, n, v, vec3(t.next(), t.next(), t.next()), l, pdf) ? 1 : 0;
    }
    valid /= kDraws;
    const double se = integral.standard_error();
    EXPECT_LE(integral.mean(), 1.0 + 5.0 * se);
    EXPECT_NEAR(integral.mean(), valid, 5.0 * std::hypot(se, std::sqrt(valid * (1 - valid) / kDraws)) + 1e-4);
  }
}

// White furnace. A white material with reflectance 0 is pure Lambert (Filament's
// f90 fades Schlick's grazing term out), so the estimator f cos / pdf over
// brdf_sample's directions averages to its albedo, 1, at every view angle
// (tolerance 5 standard errors); the Lambert part alone likewise.
TEST(SharedBrdf, WhiteFurnaceDiffuse) {
  const vec3 n = normalize(vec3(0.2f, -0.3f, 0.9f));
  for (float roughness : {1.0f, 0.5f}) {
    const BrdfParams p = brdf_params(vec3(1.0f), 0.0f, roughness, 0.0f, BRDF_SINGLE_SCATTER);
    for (float NoV : {1.0f, 0.7f, 0.3f, 0.01f}) {
      SCOPED_TRACE(::testing::Message() << "roughness " << roughness << " NoV " << NoV);
      const vec3 v = to_world(view_with(NoV), n);
      Stream s(41);
      MeanEstimate lambert, full;
      for (int i = 0; i < 200000; ++i) {
        vec3 l;
        float pdf;
        if (!brdf_sample(p, n, v, vec3(s.next(), s.next(), s.next()), l, pdf)) {
          lambert.add(0), full.add(0);
          continue;
        }
        const float cos_l = dot(n, l);
        lambert.add(double(p.diffuse_color.x * INV_PI * cos_l / pdf));
        const vec3 w = brdf_eval(p, n, v, l) * cos_l / pdf;
        ASSERT_TRUE(std::isfinite(w.x));
        full.add(double(w.x));
      }
      EXPECT_NEAR(lambert.mean(), 1.0, 5.0 * lambert.standard_error() + 1e-5);
      EXPECT_NEAR(full.mean(), 1.0, 5.0 * full.standard_error() + 1e-5);
    }
  }
}

// ∫ D(h) (n·h) dω_h = 1, by quadrature: with s = 1 − (n·h)², the integral is
// pi ∫_0^1 D ds; s is sampled on a log grid (D peaks at s ~ alpha²). D is
// evaluated at float n·h as the shader does; the tolerance is 0.2% (3% for the
// minimum roughness, where float n·h resolves the 1e-6-wide peak coarsely).
TEST(SharedBrdf, GgxNormalDistributionIsNormalised) {
  for (float perceptual : {MIN_PERCEPTUAL_ROUGHNESS, 0.1f, 0.3f, 0.6f, 1.0f}) {
    const float alpha = brdf_params(vec3(1.0f), 0.0f, perceptual, 0.5f, BRDF_SINGLE_SCATTER).alpha;
    double integral = 0;
    const int kSteps = 400000;
    const double log_lo = std::log(1e-14), log_hi = 0.0;
    double s_prev = 0.0, d_prev = D_GGX(alpha, 1.0f);
    for (int i = 0; i <= kSteps; ++i) {
      const double s = std::exp(log_lo + (log_hi - log_lo) * i / kSteps);
      const double d = D_GGX(alpha, float(std::sqrt(1.0 - s)));
      integral += 0.5 * (d + d_prev) * (s - s_prev);  // trapezoid
      s_prev = s, d_prev = d;
    }
    integral *= PI;
    EXPECT_NEAR(integral, 1.0, perceptual <= MIN_PERCEPTUAL_ROUGHNESS ? 0.03 : 2e-3) << "perceptual roughness " << perceptual;
  }
}

bool finite(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The hard cases of the `finite` check: perceptual roughness 0 (clamped),
// grazing and exactly tangent views, l ≈ v, l = mirror, black base colour.
TEST(SharedBrdf, NoNonFiniteValuesOnHardCases) {
  const vec3 n(0.0f, 0.0f, 1.0f);
  std::vector<vec3> views = {n, view_with(1e-3f), view_with(1e-7f), vec3(1.0f, 0.0f, 0.0f),
                             normalize(vec3(1.0f, 0.0f, -1e-7f))};
  std::vector<float> us = {0.0f, 1e-7f, 0.5f, 0.99999994f};
  for (float roughness : {0.0f, 1e-4f, MIN_PERCEPTUAL_ROUGHNESS, 0.5f}) {
    for (float metallic : {0.0f, 1.0f}) {
      for (vec3 base : {vec3(0.0f), vec3(1.0f), vec3(0.5f, 0.2f, 0.9f)}) {
        const BrdfParams p = brdf_params(base, metallic, roughness, 0.5f, BRDF_SINGLE_SCATTER);
        ASSERT_GE(p.alpha, MIN_PERCEPTUAL_ROUGHNESS * MIN_PERCEPTUAL_ROUGHNESS);
        for (const vec3& v : views) {
          std::vector<vec3> lights = {v, normalize(v + vec3(1e-6f, 0.0f, 0.0f)), reflect(-v, n), n,
                                      view_with(1e-7f), normalize(vec3(-1.0f, 0.0f, 1e-6f))};
          for (const vec3& l : lights) {
            ASSERT_TRUE(finite(brdf_eval(p, n, v, l))) << roughness << " " << metallic;
            ASSERT_TRUE(std::isfinite(brdf_pdf(p, n, v, l))) << roughness << " " << metallic;
          }
          for (float a : us)
            for (float b : us)
              for (float c : us) {
                vec3 l(0.0f);
                float pdf = 0.0f;
                if (brdf_sample(p, n, v, vec3(a, b, c), l, pdf)) {
                  ASSERT_TRUE(finite(l));
                  ASSERT_TRUE(std::isfinite(pdf));
                  ASSERT_GT(pdf, 0.0f);
                  const vec3 w = brdf_eval(p, n, v, l) * std::max(dot(n, l), 0.0f) / pdf;
                  ASSERT_TRUE(finite(w)) << roughness << " " << metallic << " " << a << " " << b << " " << c;
                }
              }
        }
      }
    }
  }
}

}  // namespace
