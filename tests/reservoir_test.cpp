// CPU tests of core/shared/reservoir.h and restir_di.h, the code the ReSTIR
// DI shaders run: the balance heuristic, pixel_dissimilar, and that RIS and
// pairwise merging keep f(x)·W an unbiased estimate of Σf on a known discrete
// distribution. Statistical thresholds are 5 standard errors (fixed seeds).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "core/shared/reservoir.h"
#include "core/shared/restir_di.h"
#include "core/shared/rng.h"

namespace {

using namespace gi::shader;

TEST(BalanceHeuristic, MatchesTheDefinitionAndItsEdgeCases) {
  EXPECT_EQ(balance_mis(0.0f, 3.0f), 0.0f);
  EXPECT_EQ(balance_mis(0.0f, 0.0f), 0.0f);
  EXPECT_FLOAT_EQ(balance_mis(1.0f, 1.0f), 0.5f);
  EXPECT_FLOAT_EQ(balance_mis(2.0f, 1.0f), 2.0f / 3.0f);
  EXPECT_EQ(balance_mis(1.0f, INFINITY), 0.0f);
  EXPECT_FLOAT_EQ(balance_mis(5.0f, 0.0f), 1.0f);
  for (float a : {0.1f, 1.0f, 7.0f})
    for (float b : {0.3f, 2.0f, 40.0f}) EXPECT_NEAR(balance_mis(a, b) + balance_mis(b, a), 1.0f, 1e-6f);
}

TEST(PixelDissimilar, TangentPlaneDistanceAndNormalAngle) {
  const vec3 p(0.0f, 0.0f, -10.0f), n(0.0f, 0.0f, 1.0f);
  const float z = 10.0f;
  EXPECT_FALSE(pixel_dissimilar(z, p, p + vec3(0.5f, 0.0f, 0.0f), n, n, 0.003f, 0.906f));  // in plane
  EXPECT_FALSE(pixel_dissimilar(z, p, p + vec3(0.0f, 0.0f, 0.02f), n, n, 0.003f, 0.906f));  // 0.002 · z
  EXPECT_TRUE(pixel_dissimilar(z, p, p + vec3(0.0f, 0.0f, 0.04f), n, n, 0.003f, 0.906f));   // 0.004 · z
  const float d20 = 20.0f * PI / 180.0f, d30 = 30.0f * PI / 180.0f;
  EXPECT_FALSE(pixel_dissimilar(z, p, p, n, vec3(std::sin(d20), 0.0f, std::cos(d20)), 0.003f, 0.906f));
  EXPECT_TRUE(pixel_dissimilar(z, p, p, n, vec3(std::sin(d30), 0.0f, std::cos(d30)), 0.003f, 0.906f));
}

// A toy "light set": item i has contribution f[i]; reservoirs pick items.
struct Toy {
  std::vector<float> f;
  float total() const {
    float s = 0;
    for (float v : f) s += v;
    return s;
  }
};

// RIS over `candidates` uniform picks with target p̂ (the light-tile pattern).
DiReservoir ris(const Toy& toy, const std::function<float(uint)>& target, uint candidates, uint& rng) {
  RisStream s = ris_begin();
  DiReservoir r = empty_di_reservoir();
  r.confidence_weight = 1.0f;
  const float inverse_pdf = float(toy.f.size());
  for (uint i = 0; i < candidates; ++i) {
    const uint k = std::min(uint(rng_next_float(rng) * toy.f.size()), uint(toy.f.size()) - 1u);
    const float t = target(k);
    if (ris_update(s, t * inverse_pdf / float(candidates), t, rng_next_float(rng))) {
      r.light.light_id = k;
      r.light.valid = 1u;
    }
  }
  r.unbiased_contribution_weight = ris_contribution_weight(s);
  return r;
}

struct Estimate {
  double mean, standard_error;
};

Estimate run(int trials, const std::function<double(uint&)>& one) {
  uint rng = rng_seed(7u, 0x1234u, 0u, 0u);
  double sum = 0, sum2 = 0;
  for (int t = 0; t < trials; ++t) {
    const double v = one(rng);
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / trials;
  return {mean, std::sqrt(std::max(0.0, sum2 / trials - mean * mean) / trials)};
}

const Toy kToy{{0.0f, 1.0f, 4.0f, 0.5f, 2.0f, 0.0f, 8.0f, 0.25f}};

TEST(Ris, FTimesWIsUnbiasedForAnyPositiveTarget) {
  // Target deliberately unlike f (but positive wherever f is).
  auto target = [](uint k) { return 1.0f + float(k % 3); };
  const Estimate e = run(200000, [&](uint& rng) {
    const DiReservoir r = ris(kToy, target, 4, rng);
    return di_reservoir_valid(r) ? double(kToy.f[r.light.light_id]) * r.unbiased_contribution_weight : 0.0;
  });
  EXPECT_NEAR(e.mean, kToy.total(), 5.0 * e.standard_error) << "standard error " << e.standard_error;
}

// Merging a canonical reservoir (target p_c = f) with another pixel's (target
// p_o): f(x)·W of the merge must still average Σf.
Estimate merged_estimate(bool balance, const std::function<float(uint)>& p_o, float other_confidence) {
  auto p_c = [](uint k) { return kToy.f[k]; };
  return run(200000, [&](uint& rng) {
    DiReservoir c = ris(kToy, p_c, 4, rng);
    DiReservoir o = ris(kToy, p_o, 4, rng);
    o.confidence_weight = other_confidence;
    MergeTargets t;
    t.pc_xc = di_reservoir_valid(c) ? p_c(c.light.light_id) : 0.0f;
    t.po_xc = di_reservoir_valid(c) ? p_o(c.light.light_id) : 0.0f;
    t.po_xo = di_reservoir_valid(o) ? p_o(o.light.light_id) : 0.0f;
    t.pc_xo = di_reservoir_valid(o) ? p_c(o.light.light_id) : 0.0f;
    const MergeResult m = merge_di_reservoirs(c, o, t, balance, rng_next_float(rng));
    EXPECT_EQ(m.merged.confidence_weight, 1.0f + other_confidence);
    return di_reservoir_valid(m.merged) ? double(kToy.f[m.merged.light.light_id]) * m.merged.unbiased_contribution_weight
                                        : 0.0;
  });
}

TEST(ReservoirMerge, BalanceHeuristicPreservesTheUnbiasedContributionWeight) {
  auto p_o = [](uint k) { return 0.5f + kToy.f[(k + 1) % kToy.f.size()]; };  // full support, different shape
  for (float confidence : {1.0f, 20.0f}) {
    const Estimate e = merged_estimate(true, p_o, confidence);
    EXPECT_NEAR(e.mean, kToy.total(), 5.0 * e.standard_error) << "confidence " << confidence;
  }
}

TEST(ReservoirMerge, ConstantMisIsUnbiasedOnlyWhenTheOtherTargetCoversTheDomain) {
  auto covering = [](uint k) { return 0.5f + kToy.f[(k + 1) % kToy.f.size()]; };
  const Estimate ok = merged_estimate(false, covering, 20.0f);
  EXPECT_NEAR(ok.mean, kToy.total(), 5.0 * ok.standard_error);
  // The other pixel cannot produce item 6 (e.g. occluded there): constant
  // weights still give it 20/21 of the say, so that light's share is lost;
  // the balance heuristic hands item 6 entirely to the canonical reservoir.
  auto partial = [](uint k) { return k == 6u ? 0.0f : 0.5f + kToy.f[k]; };
  const Estimate constant = merged_estimate(false, partial, 20.0f);
  const Estimate balance = merged_estimate(true, partial, 20.0f);
  EXPECT_LT(constant.mean, kToy.total() - 10.0 * constant.standard_error);
  EXPECT_NEAR(balance.mean, kToy.total(), 5.0 * balance.standard_error);
}

}  // namespace
