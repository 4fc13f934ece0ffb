// Speed against error at equal time (replay/equal_time.h) and the per-signal
// figures (replay/signal_figures.h): the cost model, the peers' sample
// indices kept apart from the reference's (shown by their error, which a
// shared sample would pull below the noise), the GPU path tracer's DI mode
// against Embree's, and the per-signal noises adding up to the output's.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/cache_root.h"
#include "core/metrics.h"
#include "core/reference/embree_reference.h"
#include "core/scenes/cornell_box.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "replay/equal_time.h"
#include "replay/signal_figures.h"
#include "reports/summary.h"
#include "tests/test_support.h"

namespace gi {
namespace {

TEST(EqualTime, CostModelAndEqualErrorTime) {
  // A renderer that costs 2 ms + 0.5 ms per sample (a slow first call, as a
  // machine's noise would make it, is left out by the fastest-of rule).
  int calls = 0;
  const RenderCost c = measure_cost([&](std::uint32_t spp) { return (calls++ == 0 ? 50.0 : 2.0) + 0.5 * spp; });
  EXPECT_NEAR(c.fixed_ms, 2.0, 1e-9);
  EXPECT_NEAR(c.per_spp_ms, 0.5, 1e-9);
  EXPECT_EQ(c.spp_within(12.0), 20u);
  EXPECT_EQ(c.spp_within(1.0), 1u);  // at least one sample
  // v1 = 0.4 per sample, reference noise 0.01: error 0.05 needs 0.4 / 0.04 = 10 spp = 7 ms.
  EXPECT_NEAR(*equal_error_ms(c, 0.4, 0.01, 0.05), 7.0, 1e-9);
  EXPECT_FALSE(equal_error_ms(c, 0.4, 0.01, 0.01).has_value());  // no estimate shows less than the reference's noise
  EXPECT_FALSE(equal_error_ms(c, 0.4, 0.01, std::nan("")).has_value());
}

// The realtime budget is one chain's: the passes run per chain count once
// with two chains, the shared ones whole, the observation passes not at all.
TEST(EqualTime, OneChainBudgetCountsPerChainPassesOnce) {
  const nlohmann::json timings = {{"passes",
                                   {{"gbuffer_resolve", {{"median_ms", 1.0}}},
                                    {"di_initial_temporal", {{"median_ms", 4.0}}},
                                    {"gi_spatial_shade", {{"median_ms", 6.0}}},
                                    {"world_cache_decay", {{"median_ms", 2.0}}},
                                    {"frame_output", {{"median_ms", 9.0}}}}}};
  EXPECT_DOUBLE_EQ(pipeline_ms_per_frame(timings), 13.0);
  EXPECT_DOUBLE_EQ(one_chain_ms_per_frame(timings, 2), 8.0);
  EXPECT_DOUBLE_EQ(one_chain_ms_per_frame(timings, 1), 13.0);
  const nlohmann::json ms = signal_ms(timings, 2);
  EXPECT_DOUBLE_EQ(ms["di"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(ms["gi"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(ms["shared"].get<double>(), 1.0);
  EXPECT_FALSE(ms.contains("frame_output"));
}

struct SmallCornell {
  Scene scene = make_cornell_box();
  ReferenceOptions options;
  ReferenceResult reference;
  SmallCornell(bool direct_only) {
    options.width = 40;
    options.height = 24;
    options.spp = 64;
    options.seed = 9;
    options.direct_only = direct_only;
    reference = render_reference(scene, options);
  }
  double reference_noise() const { return estimator_noise(reference.half_a, reference.half_b, reference.mean); }
  // relMSE against the reference over the error two independent estimates would show.
  double over_expected(const ReferenceResult& peer) const {
    return relmse(peer.mean, reference.mean) /
           (estimator_noise(peer.half_a, peer.half_b, reference.mean) + reference_noise());
  }
};

// The peers draw samples the reference never used. What that buys: a peer on
// the reference's own sample indices (32 of its 64) shows an error well below
// what two independent estimates would, which makes a path tracer look
// better at equal time than it is; on fresh indices the error is as expected.
TEST(EqualTime, EmbreePeerUsesSampleIndicesTheReferenceDidNot) {
  const SmallCornell c(false);
  ReferenceOptions shared = c.options;
  shared.spp = 32;
  shared.first_sample = 0;
  EXPECT_LT(c.over_expected(render_reference(c.scene, shared)), 0.6);
  shared.first_sample = c.options.spp;
  EXPECT_GT(c.over_expected(render_reference(c.scene, shared)), 0.7);

  EqualTimeTarget t;
  t.scene = &c.scene;
  t.reference_options = c.options;
  t.reference = &c.reference;
  t.realtime = {20.0, 0.1, 0.01, 16};
  const nlohmann::json eq = equal_time_figures(nullptr, nullptr, t);
  ASSERT_TRUE(eq.contains("embree")) << eq.dump(2);
  EXPECT_FALSE(eq.contains("gpu_path_tracer"));
  const nlohmann::json& e = eq["embree"];
  EXPECT_GE(e["sample_indices"][0].get<std::uint32_t>(), c.options.spp) << e.dump(2);
  EXPECT_EQ(eq["reference"]["sample_indices"], nlohmann::json({0, 64}));
  EXPECT_GE(e["spp"].get<std::uint32_t>(), 1u);
  EXPECT_GT(e["relmse_over_expected"].get<double>(), 0.6) << e.dump(2);
  EXPECT_LT(e["relmse_over_expected"].get<double>(), 1.6) << e.dump(2);
}

// The GPU path tracer beside it, on the test device: fresh indices, its own
// RNG domain, an error as two independent estimates show; its DI mode
// estimates what Embree's does, and the full path tracer against the DI
// reference does not (so the agreement is measured, not given).
TEST(EqualTime, GpuPathTracerPeerOnTheSameDevice) {
  gpu::Device device(std::nullopt, test::test_backend());
  gpu::ShaderCompiler compiler(cache_root());
  for (bool direct_only : {false, true}) {
    const SmallCornell c(direct_only);
    EqualTimeTarget t;
    t.scene = &c.scene;
    t.reference_options = c.options;
    t.reference = &c.reference;
    t.realtime = {20.0, 0.1, 0.01, 16};
    t.embree = false;
    const nlohmann::json eq = equal_time_figures(&device, &compiler, t);
    ASSERT_TRUE(eq.contains("gpu_path_tracer")) << eq.dump(2);
    const nlohmann::json& g = eq["gpu_path_tracer"];
    SCOPED_TRACE(g.dump(2));
    EXPECT_GE(g["sample_indices"][0].get<std::uint32_t>(), c.options.spp);
    EXPECT_EQ(g["rng_domain"], "gpu_reference");
    EXPECT_GT(g["ms"].get<double>(), 0.0);
    EXPECT_GT(g["relmse_over_expected"].get<double>(), 0.6);
    EXPECT_LT(g["relmse_over_expected"].get<double>(), 1.6);
  }
  // The full image against the DI reference: far outside the noise. The
  // bias stays while the noise falls with the samples the budget buys, so
  // the budget is ten frames' worth: at 20 ms a loaded 2-core lavapipe
  // bought 3 samples (4.7 ms each) and the ratio read 2.5; at 200 ms it
  // buys about 40, and still 12 on a machine three times as slow.
  const SmallCornell di(true);
  EqualTimeTarget t;
  t.scene = &di.scene;
  t.reference_options = di.options;
  t.reference_options.direct_only = false;
  t.reference = &di.reference;
  t.realtime = {200.0, 0.1, 0.01, 16};
  t.embree = false;
  const nlohmann::json eq = equal_time_figures(&device, &compiler, t);
  EXPECT_GT(eq["gpu_path_tracer"]["relmse_over_expected"].get<double>(), 3.0) << eq.dump(2);
}

Image random_image(std::mt19937& rng, float sigma, float offset = 0.5f) {
  std::normal_distribution<float> n(0.0f, sigma);
  Image im(48, 32);
  for (glm::vec3& p : im.pixels) p = glm::vec3(offset + n(rng), offset + n(rng), offset + n(rng));
  return im;
}

// Independent signal noises add up (the cross term within its standard
// error); two signals that share their noise do not, and the figure says so.
TEST(SignalFigures, ChainNoisesAddUpOnlyWhenTheSignalsAreIndependent) {
  std::mt19937 rng(7);
  Image m(48, 32);
  for (glm::vec3& p : m.pixels) p = glm::vec3(1.0f);
  const std::vector<Image> a = {random_image(rng, 0.2f), random_image(rng, 0.3f), random_image(rng, 0.05f)};
  const std::vector<Image> b = {random_image(rng, 0.2f), random_image(rng, 0.3f), random_image(rng, 0.05f)};
  const NoiseAdditivity ok = chain_noise_additivity(a, b, m);
  EXPECT_NEAR(ok.output, ok.sum_of_signals + ok.cross_term, 1e-9);
  EXPECT_GT(ok.cross_term_standard_error, 0.0);
  EXPECT_LT(std::abs(ok.cross_term), 3.0 * ok.cross_term_standard_error);
  // The second signal a copy of the first: the same noise twice.
  const NoiseAdditivity shared = chain_noise_additivity({a[0], a[0], a[2]}, {b[0], b[0], b[2]}, m);
  EXPECT_GT(shared.cross_term, 10.0 * shared.cross_term_standard_error);
}

// On the pipeline: a realtime GI run's chain noises (DI, GI, specular) add up
// to the output's within their statistical error, and the run's equal-time
// block has both peers and each signal's figures.
TEST(SignalFigures, RealtimeRunSignalsAddUpAndCarryBiasAndMs) {
  test::TempDir dir("equal_time_run");
  const test::CommandResult r = test::run_giharness(
      "run " + (test::source_dir() / "tests/data/suites/realtime/rt_cornell_gi.json").string() +
      " --equal-time --out " + dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = test::read_json(dir.path() / "summary.json");
  const nlohmann::json& add = s["noise"]["chain"]["additivity"];
  SCOPED_TRACE(add.dump(2));
  EXPECT_GT(add["output"].get<double>(), 0.0);
  EXPECT_LT(std::abs(add["output"].get<double>() - add["sum_of_signals"].get<double>()),
            3.0 * add["cross_term_standard_error"].get<double>());
  const nlohmann::json& eq = s["equal_time"];
  for (const char* peer : {"gpu_path_tracer", "embree"}) {
    ASSERT_TRUE(eq.contains(peer)) << eq.dump(2);
    EXPECT_TRUE(eq[peer]["equal_error_time_ratio_frame"].is_number()) << eq[peer].dump(2);
  }
  for (const char* signal : {"di", "gi", "specular"}) {
    EXPECT_TRUE(eq["signals"][signal]["noise_chain"].is_number()) << signal;
    EXPECT_TRUE(eq["signals"][signal]["ms"].is_number()) << signal;
  }
  EXPECT_TRUE(eq["signals"]["di"]["bias"]["relmse"].is_number());
  EXPECT_TRUE(eq["signals"]["indirect"]["bias"]["relmse"].is_number());
}

}  // namespace
}  // namespace gi
