// The ray_budget check end to end on lavapipe: it fails on the bug it exists
// for (Bevy #23898: glossy paths without Russian roulette,
// scenarios/bugs/bevy_23898_no_specular_roulette.json), passes on the fix,
// counts the same on every run, leaves the pipeline's output alone, and is
// refused where specular GI does not run.
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json budget(const std::filesystem::path& out) { return test::check_result(out, "ray_budget"); }

TEST(RayBudgetCheck, FailsWithoutTheRouletteAndPassesWithIt) {
  test::TempDir dir("ray_budget");
  const std::string bug_file = (test::source_dir() / "scenarios/bugs/bevy_23898_no_specular_roulette.json").string();
  const auto bug = test::run_giharness("run " + bug_file + " --out " + (dir.path() / "bug").string());
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = budget(dir.path() / "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  EXPECT_GT(b["figures"]["rays_per_path"].get<double>(), 1.6);

  const std::string fix_file = (test::source_dir() / "scenarios/specular_ray_budget_mirror.json").string();
  const auto fix = test::run_giharness("run " + fix_file + " --out " + (dir.path() / "fix").string());
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json f = budget(dir.path() / "fix");
  EXPECT_EQ(f.at("verdict"), "pass");
  // The same pixels trace a path either way; the roulette only ends them sooner.
  EXPECT_EQ(f["figures"]["paths"], b["figures"]["paths"]);
  EXPECT_LT(f["figures"]["rays"].get<double>(), b["figures"]["rays"].get<double>());
  // Counted, not timed: a second run gives the same figures.
  const auto again = test::run_giharness("run " + fix_file + " --out " + (dir.path() / "again").string());
  EXPECT_EQ(budget(dir.path() / "again")["figures"], f["figures"]);
}

// The counters are instrumentation: the images are the same bits with or
// without the check, and without it the counters' buffer is not in the state.
TEST(RayBudgetCheck, CountingLeavesTheImageAlone) {
  test::TempDir dir("ray_budget_bits");
  // The counters (GI_PATH_COUNTERS) serve spatial_acceptance too: the Cornell
  // scenario that runs it compiles faster than the mirror room.
  const auto [a, b] = test::run_with_and_without_checks("scenarios/gi_spatial_search_cornell.json", dir.path(), 3);
  ASSERT_FALSE(a.empty() || b.empty());
  EXPECT_EQ(a["hashes"]["frame_images"], b["hashes"]["frame_images"]);
  EXPECT_EQ(a["hashes"]["final_buffers"]["gi/output"], b["hashes"]["final_buffers"]["gi/output"]);
  EXPECT_EQ(a["hashes"]["final_buffers"]["specular/output"], b["hashes"]["final_buffers"]["specular/output"]);
  EXPECT_EQ(a["hashes"]["final_buffers"]["gi/stats"], b["hashes"]["final_buffers"]["gi/stats"]);
  EXPECT_TRUE(a["hashes"]["final_buffers"].contains("gi/counters"));
  EXPECT_FALSE(b["hashes"]["final_buffers"].contains("gi/counters"));
}

TEST(RayBudgetCheck, RefusedWithoutSpecularGiOrABudget) {
  test::TempDir dir("ray_budget_bad");
  const auto no_specular = test::write_scenario_variant(
      "scenarios/specular_ray_budget_mirror.json", dir.path(), "no_specular.json",
      [](nlohmann::json& doc) { doc["overrides"]["specular.enabled"] = false; });
  const auto r = test::run_giharness("run " + no_specular.string() + " --out " + (dir.path() / "a").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/1"), std::string::npos) << r.output;
  const auto no_budget = test::write_scenario_variant(
      "scenarios/specular_ray_budget_mirror.json", dir.path(), "no_budget.json",
      [](nlohmann::json& doc) { doc["checks"][1].erase("max_rays_per_path"); });
  const auto s = test::run_giharness("run " + no_budget.string() + " --out " + (dir.path() / "b").string());
  EXPECT_EQ(s.exit_code, 2) << s.output;
  EXPECT_NE(s.output.find("max_rays_per_path"), std::string::npos) << s.output;
}

}  // namespace
}  // namespace gi
