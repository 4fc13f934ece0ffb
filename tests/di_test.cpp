// Realtime DI end to end, on the shipped DI scenarios run through
// the giharness binary: the packing-range energy loss of plain rgb9e5 (0.17)
// is caught with the measured ratio in the message and goes away when only the
// packing is switched; the 0.17 visibility order (spatial ray fed forward)
// leaves more error near shadow edges than 0.18's. Each run is 160x90, 32
// frames; the Embree DI references are cached after the first run.
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

#include "test_support.h"

namespace gi {
namespace {

struct DiRun {
  int exit_code;
  std::string output;
  nlohmann::json reference;  // the reference check's last compared frame
  std::string message;
};

DiRun run(const std::string& scenario, const std::string& extra, const std::string& tag) {
  test::TempDir dir("di_" + tag);
  const auto r = test::run_giharness("run " + (test::source_dir() / "scenarios" / scenario).string() + " " + extra +
                                     " --out " + dir.path().string());
  DiRun out{r.exit_code, r.output, {}, {}};
  const nlohmann::json s = test::read_json(dir.path() / "summary.json");
  for (const auto& c : s["checks"])
    if (c["name"] == "reference") {
      out.reference = c["figures"]["frames"].back();
      out.message = c["message"].get<std::string>();
    }
  return out;
}

double energy(const DiRun& r) { return r.reference["temporal_mean"]["energy_ratio"].get<double>(); }
double sigma(const DiRun& r) { return r.reference["temporal_mean"]["energy_ratio_sigma"].get<double>(); }

TEST(RealtimeDi, PlainRgb9e5PackingLosesTheBrightEmitterAndTheCheckSaysHowMuch) {
  // Only the packing differs between the two runs (0.18 profile, 0.17 packing).
  const DiRun plain = run("di_packing_range.json", "--set light_tiles.radiance_encoding=plain", "packing_plain");
  ASSERT_EQ(plain.exit_code, 1) << plain.output;
  EXPECT_LT(energy(plain), 0.5) << plain.message;  // the 3e5 emitter is clipped to 65408
  // The message carries the measured ratio.
  EXPECT_NE(plain.message.find(fmt::format("energy ratio {:.4f}", energy(plain))), std::string::npos)
      << plain.message;

  // Switching only the packing back to log2 makes the check pass.
  const DiRun log2 = run("di_packing_range.json", "", "packing_log2");
  EXPECT_EQ(log2.exit_code, 0) << log2.message;
  // 8 chains, tolerance 2 %: the margin is Student's t with 7 degrees of freedom (4.53 sigma).
  EXPECT_LT(std::abs(energy(log2) - 1.0), 0.02 + 4.53 * sigma(log2)) << log2.message;
}

TEST(RealtimeDi, Solari018MatchesTheEmbreeDirectLightingOnEveryDiScene) {
  for (const char* scene : {"di_cornell_box.json", "di_many_lights.json", "di_moving_occluder.json"}) {
    const DiRun r = run(scene, "", "match");
    EXPECT_EQ(r.exit_code, 0) << scene << ": " << r.message;
    EXPECT_LT(std::abs(energy(r) - 1.0), 0.01 + 3.0 * sigma(r)) << scene << ": " << r.message;
    EXPECT_LE(r.reference["temporal_mean"]["relmse_over_noise"].get<double>(), 3.0) << scene << ": " << r.message;
  }  // di_packing_range.json: PlainRgb9e5PackingLoses... above
}

TEST(RealtimeDi, ReleasedInitialVisibilityFedForwardDarkensDirectLightAndTheCheckSaysSo) {
  // The same scene and frames as di_moving_occluder.json, with 0.18's initial
  // shadow ray fed forward into reuse as released (README, "DI bias").
  const DiRun released = run("expected_failures/di_released_0_18_initial_visibility.json", "", "released");
  ASSERT_EQ(released.exit_code, 1) << released.output;
  EXPECT_LT(energy(released), 0.95) << released.message;
  EXPECT_NE(released.message.find(fmt::format("energy ratio {:.4f}", energy(released))), std::string::npos)
      << released.message;
  // Switching only that back (the shipped scenario) removes the darkening.
  const DiRun fixed = run("di_moving_occluder.json", "", "released_fixed");
  EXPECT_GT(energy(fixed) - energy(released), 0.05) << fixed.message << " vs " << released.message;
}

TEST(RealtimeDi, FedForwardSpatialVisibilityLeavesMoreErrorAtShadowEdgesThanTheFinalRay) {
  const DiRun final_ray = run("di_moving_occluder.json", "", "vis_final");
  const DiRun fed = run("di_moving_occluder.json", "--set restir_di.visibility=spatial_fed_forward", "vis_fed");
  // (Both runs keep the initial ray out of reuse: only the second ray's place differs.)
  const double e18 = final_ray.reference["temporal_mean_edge_region_relmse"].get<double>();
  const double e17 = fed.reference["temporal_mean_edge_region_relmse"].get<double>();
  EXPECT_GT(e17, 1.5 * e18) << "edge-region relMSE: fed forward " << e17 << ", final ray " << e18;
}

TEST(RealtimeDi, FinalVisibilityStoredInReuseDarkensMoreThanThe017Order) {
  // Bevy #21649 moved DI's shadow ray to the final sample and folded it into
  // the stored W (restir_di.visibility final_stored); #22033 stopped storing
  // it. In the moving-occluder scene the stored ray darkens more than 0.17's
  // order (measured 2026-12-03: 0.625 against 0.717 and 0.9988), so the
  // pre-#21649 state cannot be called the bug: the museum counts #21649 missed.
  const DiRun stored = run("di_moving_occluder.json", "--set restir_di.visibility=final_stored", "vis_stored");
  const DiRun fed = run("di_moving_occluder.json", "--set restir_di.visibility=spatial_fed_forward", "vis_fed17");
  const DiRun final_ray = run("di_moving_occluder.json", "", "vis_final18");
  EXPECT_EQ(stored.exit_code, 1) << stored.message;
  EXPECT_EQ(fed.exit_code, 1) << fed.message;
  EXPECT_EQ(final_ray.exit_code, 0) << final_ray.message;
  EXPECT_LT(energy(stored), energy(fed) - 0.05) << stored.message << " vs " << fed.message;
  EXPECT_LT(energy(fed), 0.8) << fed.message;
}

}  // namespace
}  // namespace gi
