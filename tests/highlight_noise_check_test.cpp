// The highlight_noise check end to end on lavapipe: it fails on the bug it
// exists for (Bevy #22313: DI sampling lights for a mirror's lobe,
// scenarios/bugs/bevy_22313_di_samples_the_mirror_lobe.json), passes on the
// fix (specular GI takes the lobe), and needs its limit from the scenario.
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json noise(const std::filesystem::path& out) { return test::check_result(out, "highlight_noise"); }

TEST(HighlightNoiseCheck, FailsWhenDiSamplesTheMirrorLobeAndPassesWithTheHandover) {
  test::TempDir dir("highlight_noise");
  const std::string bug_file =
      (test::source_dir() / "scenarios/bugs/bevy_22313_di_samples_the_mirror_lobe.json").string();
  const auto bug = test::run_giharness("run " + bug_file + " --out " + (dir.path() / "bug").string());
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = noise(dir.path() / "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  EXPECT_GT(b["figures"]["mean_relmse"].get<double>(), 0.5);
  EXPECT_GT(b["figures"]["highlight_pixels"].get<int>(), 10);

  const std::string fix_file = (test::source_dir() / "scenarios/gi_mirror_highlights.json").string();
  const auto fix = test::run_giharness("run " + fix_file + " --out " + (dir.path() / "fix").string());
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json f = noise(dir.path() / "fix");
  EXPECT_EQ(f.at("verdict"), "pass");
  EXPECT_LT(f["figures"]["mean_relmse"].get<double>(), 0.01);
  // The region comes from the reference alone: the same pixels either way.
  EXPECT_EQ(f["figures"]["highlight_pixels"], b["figures"]["highlight_pixels"]);
}

TEST(HighlightNoiseCheck, RefusedWithoutALimitOrGi) {
  test::TempDir dir("highlight_noise_bad");
  const auto no_limit = test::write_scenario_variant("scenarios/gi_mirror_highlights.json", dir.path(), "no_limit.json",
                                                     [](nlohmann::json& doc) { doc["checks"][1].erase("max_relmse"); });
  const auto r = test::run_giharness("run " + no_limit.string() + " --out " + (dir.path() / "a").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("max_relmse"), std::string::npos) << r.output;
  const auto no_gi = test::write_scenario_variant("scenarios/gi_mirror_highlights.json", dir.path(), "no_gi.json",
                                                  [](nlohmann::json& doc) { doc["gi"] = false; });
  const auto s = test::run_giharness("run " + no_gi.string() + " --out " + (dir.path() / "b").string());
  EXPECT_EQ(s.exit_code, 2) << s.output;
  EXPECT_NE(s.output.find("/checks/1"), std::string::npos) << s.output;
}

}  // namespace
}  // namespace gi
