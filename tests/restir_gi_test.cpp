// CPU tests of core/shared/restir_gi.h, the code the ReSTIR GI shaders run:
// the reconnection jacobian (values, reciprocity, the inf/NaN it sanitises),
// permutation sampling, the merge with jacobians, and the histogram bins.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/shared/restir_gi.h"
#include "core/shared/rng.h"

namespace {

using namespace gi::shader;

TEST(GiJacobian, OneWhenTheOriginDoesNotMoveAndInverseSquareAlongTheNormal) {
  const vec3 s(0.0f), n(0.0f, 0.0f, 1.0f);
  EXPECT_FLOAT_EQ(gi_jacobian(vec3(0.3f, 0.1f, 1.0f), vec3(0.3f, 0.1f, 1.0f), s, n), 1.0f);
  // Twice as far, both on the normal: |q|²/|r|² = 1/4.
  EXPECT_FLOAT_EQ(gi_jacobian(vec3(0, 0, 2), vec3(0, 0, 1), s, n), 0.25f);
  // Same distance, 60° off the normal at the new origin: cos 60° = 0.5.
  EXPECT_NEAR(gi_jacobian(vec3(std::sin(1.0471976f), 0, std::cos(1.0471976f)), vec3(0, 0, 1), s, n), 0.5f, 1e-6f);
}

TEST(GiJacobian, ShiftsBackAndForthCancel) {
  std::uint32_t rng = 7;
  for (int i = 0; i < 100; ++i) {
    const vec3 s(rng_next_float(rng), rng_next_float(rng), 0.0f), n(0, 0, 1);
    const vec3 a(rng_next_float(rng) * 4 - 2, rng_next_float(rng) * 4 - 2, 0.1f + rng_next_float(rng));
    const vec3 b(rng_next_float(rng) * 4 - 2, rng_next_float(rng) * 4 - 2, 0.1f + rng_next_float(rng));
    EXPECT_NEAR(gi_jacobian(a, b, s, n) * gi_jacobian(b, a, s, n), 1.0f, 1e-4f);
  }
}

TEST(GiJacobian, GrazingOrCoincidentPointsAreNonFiniteRawAndZeroSanitised) {
  const vec3 s(0.0f), n(0, 0, 1);
  // The original direction grazes the sample's surface: cos_q = 0, J = x/0 = inf.
  EXPECT_TRUE(std::isinf(gi_jacobian_raw(vec3(0, 0, 1), vec3(1, 0, 0), s, n)));
  EXPECT_FALSE(gi_finite(gi_jacobian_raw(vec3(0, 0, 1), vec3(1, 0, 0), s, n)));
  EXPECT_EQ(gi_jacobian(vec3(0, 0, 1), vec3(1, 0, 0), s, n), 0.0f);
  // The new origin on the sample point: 0/0.
  EXPECT_FALSE(gi_finite(gi_jacobian_raw(s, vec3(0, 0, 1), s, n)));
  EXPECT_EQ(gi_jacobian(s, vec3(0, 0, 1), s, n), 0.0f);
  // A corner: the sample was found edge-on from far away and is reused from
  // close by along its normal: J = 1·1 / (0.01·0.0025) ≈ 4e4 (what rejection catches).
  EXPECT_GT(gi_jacobian(vec3(0, 0, 0.05f), vec3(1, 0, 0.01f), vec3(0.0f), n), 1e4f);
}

TEST(GiPermutation, StaysWithinThreePixelsAndIsAnInvolution) {
  const ivec2 res(64, 48);
  for (std::uint32_t r = 0; r < 16; ++r) {
    std::set<std::pair<int, int>> seen;
    for (int y = 4; y < 44; ++y)
      for (int x = 4; x < 60; ++x) {
        const ivec2 q = gi_permute_pixel(ivec2(x, y), r, res);
        EXPECT_LE(std::abs(q.x - x), 3);
        EXPECT_LE(std::abs(q.y - y), 3);
        EXPECT_EQ(gi_permute_pixel(q, r, res), ivec2(x, y));
        seen.insert({q.x, q.y});
      }
    EXPECT_EQ(seen.size(), 56u * 40u);  // a permutation: no two pixels share a history
  }
  // Clamped at the border.
  EXPECT_EQ(gi_permute_pixel(ivec2(63, 47), 0u, res), ivec2(60, 44));
  EXPECT_EQ(gi_permute_pixel(ivec2(0, 0), 0u, res), ivec2(3, 3));
  EXPECT_EQ(gi_permute_pixel(ivec2(63, 47), 15u, res), ivec2(62, 46));  // ((63 + 3) ^ 3) − 3
}

GiReservoir reservoir(float radiance, float w, float m) {
  GiReservoir r = empty_gi_reservoir(m);
  r.radiance = vec4(radiance, radiance, radiance, w);
  return r;
}

TEST(GiMerge, WithUnitJacobiansItIsTheDiMerge) {
  GiMergeInputs t{2.0f, 1.0f, 3.0f, 0.5f, 1.0f, 1.0f};
  DiReservoir dc = empty_di_reservoir(), d_o = empty_di_reservoir();
  dc.light.valid = d_o.light.valid = 1u;
  dc.confidence_weight = 3.0f;
  dc.unbiased_contribution_weight = 0.7f;
  d_o.confidence_weight = 5.0f;
  d_o.unbiased_contribution_weight = 1.3f;
  const MergeTargets mt{t.pc_xc, t.po_xc, t.po_xo, t.pc_xo};
  for (float u : {0.05f, 0.5f, 0.95f}) {
    const GiMergeResult g = merge_gi_reservoirs(reservoir(1, 0.7f, 3), reservoir(2, 1.3f, 5), t, u);
    const MergeResult d = merge_di_reservoirs(dc, d_o, mt, true, u);
    EXPECT_EQ(g.selected_other, d.selected_other);
    EXPECT_FLOAT_EQ(g.merged.radiance.w, d.merged.unbiased_contribution_weight);
    EXPECT_FLOAT_EQ(gi_confidence(g.merged), 8.0f);
  }
}

TEST(GiMerge, JacobiansEnterTheWeightsAndAZeroJacobianNeverPicksTheOther) {
  // J_co scales the other sample's weight: w_o = mis_o·p_c(x_o)·o.W·J_co.
  GiMergeInputs t{1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 2.0f};
  const GiReservoir c = reservoir(1, 1.0f, 1), o = reservoir(1, 1.0f, 1);
  const float mis_c = balance_mis(1.0f, 1.0f), mis_o = balance_mis(1.0f, 2.0f);
  const GiMergeResult m = merge_gi_reservoirs(c, o, t, 0.0f);
  EXPECT_TRUE(m.selected_other);
  EXPECT_FLOAT_EQ(m.merged.radiance.w, mis_c * 1.0f + mis_o * 1.0f * 2.0f);
  t.j_co = 0.0f;
  for (float u : {0.0f, 0.5f, 0.999f}) EXPECT_FALSE(merge_gi_reservoirs(c, o, t, u).selected_other);
}

TEST(GiMerge, EmptyReservoirsCarryTheirConfidenceOnly) {
  const GiMergeInputs t{0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
  const GiMergeResult m = merge_gi_reservoirs(empty_gi_reservoir(1.0f), empty_gi_reservoir(4.0f), t, 0.3f);
  EXPECT_FALSE(gi_reservoir_valid(m.merged));
  EXPECT_EQ(gi_confidence(m.merged), 5.0f);
}

TEST(GiStatsBins, PowersOfTwoAroundOne) {
  EXPECT_EQ(gi_jacobian_bin(0.0f), 0u);
  EXPECT_EQ(gi_jacobian_bin(1.0f), 16u);
  EXPECT_EQ(gi_jacobian_bin(1.19f), 16u);
  EXPECT_EQ(gi_jacobian_bin(2.0f), 17u);
  EXPECT_EQ(gi_jacobian_bin(0.5f), 15u);
  EXPECT_EQ(gi_jacobian_bin(1e30f), 31u);
  EXPECT_EQ(gi_jacobian_bin(1e-30f), 0u);
}

TEST(GiFinite, RejectsNaNAndInfOnly) {
  EXPECT_TRUE(gi_finite(0.0f));
  EXPECT_TRUE(gi_finite(3.4e38f));
  EXPECT_FALSE(gi_finite(INFINITY));
  EXPECT_FALSE(gi_finite(-INFINITY));
  EXPECT_FALSE(gi_finite(NAN));
  GiReservoir r = reservoir(1, 1, 1);
  EXPECT_TRUE(gi_reservoir_finite(r));
  r.radiance.w = NAN;
  EXPECT_FALSE(gi_reservoir_finite(r));
}

}  // namespace
