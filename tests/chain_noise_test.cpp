// Noise estimates that hold across seeds (README "Error bars"): the Student-t
// quantile the energy verdict uses, compare_chains on synthetic chains whose
// error is partly shared by every pixel of a chain (what a world cache's
// frozen cell placement does), and, end to end on lavapipe, a reference check
// with K chains runs K pipelines that share no state.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/metrics.h"
#include "replay/run_setup.h"
#include "tests/test_support.h"

namespace gi {
namespace {

TEST(StudentT, QuantilesMatchTables) {
  // Tables (e.g. NIST/SEMATECH e-Handbook 1.3.6.7.2): t_{0.975} for 1, 3, 7, 30.
  EXPECT_NEAR(student_t_quantile(0.975, 1), 12.706, 2e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 3), 3.182, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 7), 2.365, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.975, 30), 2.042, 1e-3);
  EXPECT_NEAR(student_t_quantile(0.99865, 0), 3.0, 2e-3);  // the normal's 3 sigma
  EXPECT_NEAR(student_t_quantile(0.025, 3), -3.182, 1e-3);
  EXPECT_GT(student_t_quantile(0.99865, 7), student_t_quantile(0.99865, 30));
}

// K chains of a flat image: value 1 + a per-chain offset (shared by all its
// pixels, sd `shared`) + per-pixel noise (sd `local`); the reference exact.
std::vector<Image> chains_with_shared_error(std::size_t k, double shared, double local, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Image> out;
  for (std::size_t c = 0; c < k; ++c) {
    Image img(40, 30);
    const double offset = shared * normal(rng);
    for (auto& p : img.pixels) p = glm::vec3(float(1.0 + offset + local * normal(rng)));
    out.push_back(std::move(img));
  }
  return out;
}

Image flat(float v) {
  Image img(40, 30);
  for (auto& p : img.pixels) p = glm::vec3(v);
  return img;
}

TEST(ChainNoise, TwoChainsEqualCompareAndMoreChainsSeeTheSharedError) {
  std::mt19937 rng(7);
  const Image ref = flat(1.0f);
  // Two chains: exactly compare() with the chains as halves.
  const std::vector<Image> two = chains_with_shared_error(2, 0.0, 0.1, rng);
  Image mean = flat(0.0f);
  for (std::size_t i = 0; i < mean.size(); ++i) mean.pixels[i] = 0.5f * (two[0].pixels[i] + two[1].pixels[i]);
  const Comparison c2 = compare_chains(two, ref, ref, ref);
  const Comparison c = compare(mean, two[0], two[1], ref, ref, ref);
  EXPECT_DOUBLE_EQ(c2.noise_x, c.noise_x);
  EXPECT_DOUBLE_EQ(c2.relmse, c.relmse);
  EXPECT_EQ(c2.energy_dof, 1u);
  EXPECT_EQ(c.energy_dof, 0u);

  // A shared error of 2 % per chain: over many runs the spread of the energy
  // ratio of 8 chains' mean is 0.02 / sqrt(8); the chains' σ covers it, the
  // σ summed over pixels does not.
  double sum2 = 0, chains_sigma = 0, pixel_sigma = 0;
  const int runs = 400;
  for (int r = 0; r < runs; ++r) {
    const std::vector<Image> k8 = chains_with_shared_error(8, 0.02, 0.1, rng);
    const Comparison ck = compare_chains(k8, ref, ref, ref);
    sum2 += (ck.energy_ratio - 1.0) * (ck.energy_ratio - 1.0);
    chains_sigma += ck.energy_ratio_sigma / runs;
    Image m = flat(0.0f);
    for (const Image& k : k8)
      for (std::size_t i = 0; i < m.size(); ++i) m.pixels[i] += k.pixels[i] / 8.0f;
    pixel_sigma += mean_luminance_sigma(k8[0], k8[1]) / 2.0 / runs;  // pixels as independent, 8 chains
    EXPECT_EQ(ck.energy_dof, 7u);
  }
  const double spread = std::sqrt(sum2 / runs);
  EXPECT_NEAR(spread, 0.02 / std::sqrt(8.0), 0.0015);
  // E[s] = c4 σ, c4(8) ≈ 0.965.
  EXPECT_NEAR(chains_sigma / spread, 0.965, 0.08);
  EXPECT_LT(pixel_sigma / spread, 0.2);
}

TEST(ChainNoise, TheEnergyMarginIsTheTQuantileOfTheChainsDegreesOfFreedom) {
  Comparison c;
  c.energy_ratio = 1.10;
  c.energy_ratio_sigma = 0.02;
  // Normal: 0.1 > 0.05 + 3 x 0.02: fails.
  EXPECT_FALSE(c.judge(1e9, 0.05).passed);
  // Three chains (2 degrees of freedom): the margin is t_2's 19.2 sigma, so the
  // same figures are not beyond noise; and the σ is not well below tolerance.
  c.energy_dof = 2;
  const ComparisonVerdict v = c.judge(1e9, 0.05);
  EXPECT_FALSE(v.passed);
  EXPECT_TRUE(v.inconclusive) << v.reason;
  // The margins light_leak and the reference check share: 3 for a normal,
  // t's quantile of the same tail for 3, 7 and 15 degrees of freedom.
  EXPECT_EQ(Comparison::noise_margin(0), 3.0);
  EXPECT_NEAR(Comparison::noise_margin(3), 9.22, 0.01);
  EXPECT_NEAR(Comparison::noise_margin(7), 4.53, 0.01);
  EXPECT_NEAR(Comparison::noise_margin(15), 3.59, 0.01);
}

TEST(ChainNoise, ChainSeedsDifferFromEachOtherAndFromTheRunsSeed) {
  EXPECT_NE(independent_chain_seed(5, 1), independent_chain_seed(5, 2));
  EXPECT_NE(independent_chain_seed(5, 1), 5u);
  EXPECT_NE(independent_chain_seed(5, 1), independent_chain_seed(6, 1));
  EXPECT_EQ(independent_chain_seed(5, 1), independent_chain_seed(5, 1));
}

// End to end: a GI reference check with 4 chains judges 4 pipelines' means,
// each with a world cache of its own: their energies differ by more than a
// pixel-summed σ of one chain would allow if they shared the cache.
TEST(ChainNoise, AReferenceCheckWithFourChainsRunsFourPipelines) {
  test::TempDir dir("chain_noise_k4");
  const auto file = test::write_scenario_variant("scenarios/gi_cornell_box.json", dir.path(), "k4.json",
                                                 [](nlohmann::json& doc) {
                                                   doc["frames"] = 8;
                                                   doc["checks"] = nlohmann::json::array(
                                                       {{{"name", "reference"}, {"frames", {7}}, {"spp", 16},
                                                         {"chains", 4}, {"energy_tolerance", 0.5},
                                                         {"relmse_tolerance", 1.0}}});
                                                 });
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  ASSERT_NE(r.exit_code, 2) << r.output;
  const nlohmann::json c = test::check_result(dir.path() / "out", "reference");
  const nlohmann::json& f = c["figures"]["frames"][0];
  EXPECT_EQ(f["chains"], 4);
  EXPECT_EQ(f["energy_dof"], 3);
  EXPECT_GT(f["energy_ratio_sigma_chains"].get<double>(), 0.0);
  EXPECT_EQ(f["temporal_mean"]["energy_ratio_sigma"], f["energy_ratio_sigma_chains"]);
}

}  // namespace
}  // namespace gi
