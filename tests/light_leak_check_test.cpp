// The light_leak check end to end on lavapipe: light where the path tracer has
// shadow. It fails on the bug it exists for (the world cache's query jitter
// keys cells past a 2 cm wall, Bevy #22252 under 0.18 and #24332 under 0.19:
// scenarios/bugs/bevy_22252_leak_through_thin_wall.json), passes on the fix
// (no jitter), and is refused without GI.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json leak(const std::filesystem::path& out) { return test::check_result(out, "light_leak"); }

double shadowed_ratio(const nlohmann::json& c) { return c["figures"]["max_shadowed_energy_ratio"].get<double>(); }

TEST(LightLeakCheck, JitteredCacheLeaksThroughAThinWallAndTheFixDoesNot) {
  test::TempDir dir("light_leak");
  const std::string scenario = (test::source_dir() / "scenarios/bugs/bevy_22252_leak_through_thin_wall.json").string();
  const auto bug = test::run_giharness("run " + scenario + " --out " + (dir.path() / "bug").string());
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = leak(dir.path() / "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  EXPECT_GT(shadowed_ratio(b), 1.5);
  // The region and both images as evidence, for a person to look at.
  ASSERT_EQ(b["evidence"].size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "bug" / b["evidence"][0].get<std::string>()));

  const auto fix = test::run_giharness("run " + scenario + " --set world_cache.query_jitter=none --out " +
                                       (dir.path() / "fix").string());
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json f = leak(dir.path() / "fix");
  EXPECT_EQ(f.at("verdict"), "pass");
  EXPECT_LT(shadowed_ratio(f), 1.0);
  // The region is the reference's, so both sides judge the same pixels.
  EXPECT_EQ(b["figures"]["frames"][0]["shadowed_pixels"], f["figures"]["frames"][0]["shadowed_pixels"]);
  EXPECT_GT(f["figures"]["frames"][0]["shadowed_pixels"].get<int>(), 1000);

  // 0.19's own jitter leaks too (#24332), less: about 1.15 of the path
  // tracer's energy, within the limit's noise margin at 8 chains, so the
  // check need not fail on it (docs/statistics.md). What stays true is that
  // it leaks more than the fix.
  const auto v019 = test::run_giharness("run " + scenario + " --profile solari-0.19 --out " +
                                        (dir.path() / "v019").string());
  const nlohmann::json n = leak(dir.path() / "v019");
  EXPECT_GT(shadowed_ratio(n), shadowed_ratio(f) + 0.1) << v019.output;
}

TEST(LightLeakCheck, RefusedWithoutGi) {
  test::TempDir dir("light_leak_bad");
  const auto file = test::write_scenario_variant("scenarios/leak_thin_wall.json", dir.path(), "no_gi.json",
                                                 [](nlohmann::json& doc) { doc["gi"] = false; });
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/1"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
