// The spatial_acceptance check end to end on lavapipe: it fails on the bug it
// exists for (Bevy #22617: every spatial try from the full 30 px disk,
// scenarios/bugs/bevy_22617_fixed_spatial_disk.json), passes on the fix (the
// halving disk), and is refused where GI does not run. Solari's pick of a
// try (restir_di.spatial_disk): a try past the screen lands on its edge.
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json acceptance(const std::filesystem::path& out) { return test::check_result(out, "spatial_acceptance"); }

TEST(SpatialAcceptanceCheck, FailsOnTheFixedDiskAndPassesWithTheHalving) {
  test::TempDir dir("spatial_acceptance");
  const std::string scenario = (test::source_dir() / "scenarios/bugs/bevy_22617_fixed_spatial_disk.json").string();
  const auto bug = test::run_giharness("run " + scenario + " --out " + (dir.path() / "bug").string());
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = acceptance(dir.path() / "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  EXPECT_LT(b["figures"]["found_share"].get<double>(), 0.97);

  const auto fix = test::run_giharness("run " + scenario + " --set restir_di.spatial_search=halving --out " +
                                       (dir.path() / "fix").string());
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json f = acceptance(dir.path() / "fix");
  EXPECT_EQ(f.at("verdict"), "pass");
  // The same pixels searched (the G-buffer does not change); more found one.
  EXPECT_EQ(f["figures"]["pixels"], b["figures"]["pixels"]);
  EXPECT_GT(f["figures"]["found"].get<double>(), b["figures"]["found"].get<double>());
}

// Solari clamps a spatial try to the screen (v0.18.0 realtime/restir_gi.wgsl:183-187):
// at 80×45 a 30 px disk reaches past the edge from most pixels, and the
// clamped try lands on an edge pixel. On a panel that fills the view every
// pixel is similar to every other, so under the clamp every pixel finds a
// neighbour at its first try; the harness's earlier pick refused the tries
// off the screen, and near the corners all five can be.
TEST(SpatialAcceptanceCheck, SolarisClampedTryFindsEdgeNeighboursTheRefusedOneMisses) {
  test::TempDir dir("spatial_disk");
  const auto file = test::write_scenario_variant(
      "scenarios/gi_spatial_search_cornell.json", dir.path(), "small.json", [](nlohmann::json& doc) {
        doc["scene"]["generator"] = "gi_headon_panel";
        doc["resolution"] = {80, 45};
        doc["frames"] = 3;
        doc["overrides"].erase("restir_di.spatial_search");
        doc["checks"][1]["min_found"] = 0.0;
      });
  auto found = [&](const std::string& disk) {
    const auto r = test::run_giharness("run " + file.string() + " --set restir_di.spatial_disk=" + disk + " --out " +
                                       (dir.path() / disk).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return acceptance(dir.path() / disk)["figures"];
  };
  const nlohmann::json clamped = found("concentric_clamped"), refused = found("polar_rejected");
  EXPECT_EQ(clamped["pixels"], refused["pixels"]);
  EXPECT_EQ(clamped["found"], clamped["pixels"]) << clamped.dump();
  EXPECT_LT(refused["found_share"].get<double>(), 0.995) << refused.dump();
}

TEST(SpatialAcceptanceCheck, RefusedWithoutGi) {
  test::TempDir dir("spatial_acceptance_bad");
  const auto file = test::write_scenario_variant("scenarios/gi_spatial_search_cornell.json", dir.path(), "no_gi.json",
                                                 [](nlohmann::json& doc) { doc["gi"] = false; });
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/1"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
