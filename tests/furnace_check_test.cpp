// The furnace check: the white furnace of each Solari BRDF Bevy
// shipped or fixed. Each museum piece fails on its bug's model and passes
// with the model its fix left (scenarios/bugs/bevy_{23442,23737,24243,24246}_*),
// device-free; the quadrature it rests on meets closed forms; a furnace
// beside drawn checks still draws; bad parameters are exit 2.
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/shared/brdf.h"
#include "core/white_furnace.h"
#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json furnace(const std::filesystem::path& out) { return test::check_result(out, "furnace"); }

struct Piece {
  const char* bug;   // scenarios/bugs/<bug>.json
  const char* fix;   // the model its fix left, --set on the same scenario
  double bug_worst;  // the albedo the bug's message names
};

// One run per piece and per side: the bug fails at the figure the museum
// quotes, the same scenario with the fix's model passes.
TEST(FurnaceCheck, EachBrdfBugFailsAndItsFixPasses) {
  const Piece pieces[] = {{"bevy_23442_lambert_under_the_specular_lobe", "layered_polynomial", 1.877},
                          {"bevy_23737_polynomial_f_ab", "layered", 1.875},
                          {"bevy_24243_fresnel_layering_loses_energy", "lobes_blended_f0", 0.264},
                          {"bevy_24246_blended_f0", "lobes", 0.664}};
  test::TempDir dir("furnace");
  for (const Piece& p : pieces) {
    const std::string scenario = (test::source_dir() / "scenarios/bugs" / (std::string(p.bug) + ".json")).string();
    const auto bug_out = dir.path() / (std::string(p.bug) + "_bug");
    const auto bug = test::run_giharness("run " + scenario + " --out " + bug_out.string());
    EXPECT_EQ(bug.exit_code, 1) << bug.output;
    const nlohmann::json b = furnace(bug_out);
    EXPECT_EQ(b.at("verdict"), "fail") << p.bug;
    const double worst = p.bug_worst > 1.0 ? b["figures"]["max"]["albedo"].get<double>()
                                           : b["figures"]["min"]["albedo"].get<double>();
    EXPECT_NEAR(worst, p.bug_worst, 0.002) << p.bug;
    EXPECT_TRUE(std::filesystem::exists(bug_out / "furnace.png")) << p.bug;
    // Device-free: no frame was drawn.
    EXPECT_EQ(test::read_json(bug_out / "summary.json")["resolved"]["mode"], "device_free");

    const auto fix_out = dir.path() / (std::string(p.bug) + "_fix");
    const auto fix =
        test::run_giharness("run " + scenario + " --set brdf.model=" + p.fix + " --out " + fix_out.string());
    EXPECT_EQ(fix.exit_code, 0) << fix.output;
    EXPECT_EQ(furnace(fix_out).at("verdict"), "pass") << p.bug << " with " << p.fix;
  }
}

// The quadrature against closed forms: a white Lambert surface (reflectance
// 0 under the earlier Fresnel: no specular) reflects exactly 1, and a white
// rough single-scatter metal head on reflects 1 − ln 2.
TEST(FurnaceCheck, QuadratureMeetsClosedForms) {
  for (float nov : {0.05f, 0.5f, 1.0f})
    EXPECT_NEAR(white_albedo(shader::BRDF_SINGLE_SCATTER, 0.5f, 0.0f, 0.0f, nov), 1.0, 1e-4) << nov;
  EXPECT_NEAR(white_albedo(shader::BRDF_SINGLE_SCATTER, 1.0f, 1.0f, 0.5f, 1.0f), 1.0 - std::log(2.0), 0.002);
  // A near-mirror white metal reflects all (the VNDF estimate is G2/G1 ≈ 1).
  EXPECT_NEAR(white_albedo(shader::BRDF_SINGLE_SCATTER, 0.0316f, 1.0f, 0.5f, 1.0f), 1.0, 1e-3);
}

// Beside a check that needs drawn frames the furnace does not run alone: the
// scenario renders, and the furnace adds its verdict.
TEST(FurnaceCheck, BesideDrawnChecksTheRunStillDraws) {
  test::TempDir dir("furnace_beside");
  const auto file = test::write_scenario_variant("scenarios/furnace_metal_after_23737.json", dir.path(),
                                                 "furnace_and_finite.json",
                                                 [](nlohmann::json& doc) { doc["checks"].push_back({{"name", "finite"}}); });
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = test::read_json(dir.path() / "out" / "summary.json");
  EXPECT_NE(s["resolved"]["mode"], "device_free");
  EXPECT_EQ(s["checks"].size(), 2u);
  EXPECT_EQ(furnace(dir.path() / "out").at("verdict"), "pass");
}

TEST(FurnaceCheck, BadParametersAreExitTwoWithTheirPath) {
  test::TempDir dir("furnace_bad");
  const auto file = test::write_scenario_variant("scenarios/furnace_metal_after_23737.json", dir.path(), "bad.json",
                                                 [](nlohmann::json& doc) { doc["checks"][0]["metallic"] = {0.0, 1.5}; });
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/0/metallic/1"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
