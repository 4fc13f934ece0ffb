// The temporal_acceptance check end to end on lavapipe: it fails on the bug it
// exists for (Bevy #21722: ReSTIR GI's permuted temporal pick without a
// fallback, scenarios/bugs/bevy_21722_no_temporal_fallback.json), passes on
// the fix (the point fallback, solari-0.18's value), leaves the pipeline's
// output alone, and is refused where GI does not run.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json acceptance(const std::filesystem::path& out) { return test::check_result(out, "temporal_acceptance"); }

TEST(TemporalAcceptanceCheck, FailsWithoutTheFallbackAndPassesWithIt) {
  test::TempDir dir("temporal_acceptance");
  const std::string scenario = (test::source_dir() / "scenarios/bugs/bevy_21722_no_temporal_fallback.json").string();
  const auto bug = test::run_giharness("run " + scenario + " --out " + (dir.path() / "bug").string());
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = acceptance(dir.path() / "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  EXPECT_LT(b["figures"]["edge_reuse"].get<double>(), 0.6);
  EXPECT_GT(b["figures"]["edge_pixels"].get<int>(), 1000);

  const auto fix = test::run_giharness("run " + scenario + " --set restir_gi.temporal_fallback=point --out " +
                                       (dir.path() / "fix").string());
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json f = acceptance(dir.path() / "fix");
  EXPECT_EQ(f.at("verdict"), "pass");
  // The same edge pixels had a history; with the fallback every one reuses it.
  EXPECT_EQ(f["figures"]["edge_pixels"], b["figures"]["edge_pixels"]);
  EXPECT_EQ(f["figures"]["edge_reused"], f["figures"]["edge_pixels"]);
  // Per-frame counts in frames.jsonl.
  std::ifstream lines(dir.path() / "fix" / "frames.jsonl");
  std::string line;
  int recorded = 0;
  while (std::getline(lines, line)) recorded += nlohmann::json::parse(line).contains("temporal_acceptance");
  EXPECT_EQ(recorded, 7);
}

// The counters are instrumentation: the images are the same bits with or
// without the check.
TEST(TemporalAcceptanceCheck, CountingLeavesTheImageAlone) {
  test::TempDir dir("temporal_acceptance_bits");
  const auto [a, b] = test::run_with_and_without_checks("scenarios/gi_edge_reuse_cornell.json", dir.path(), 3);
  ASSERT_FALSE(a.empty() || b.empty());
  EXPECT_EQ(a["hashes"]["frame_images"], b["hashes"]["frame_images"]);
  EXPECT_EQ(a["hashes"]["final_buffers"]["gi/output"], b["hashes"]["final_buffers"]["gi/output"]);
  EXPECT_EQ(a["hashes"]["final_buffers"]["gi/stored_reservoirs"], b["hashes"]["final_buffers"]["gi/stored_reservoirs"]);
  // The statistics themselves differ: the counts are in them.
  EXPECT_NE(a["hashes"]["final_buffers"]["gi/stats"], b["hashes"]["final_buffers"]["gi/stats"]);
}

TEST(TemporalAcceptanceCheck, RefusedWithoutGi) {
  test::TempDir dir("temporal_acceptance_bad");
  const auto file = test::write_scenario_variant("scenarios/gi_edge_reuse_cornell.json", dir.path(), "no_gi.json",
                                                 [](nlohmann::json& doc) { doc["gi"] = false; });
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/0"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
