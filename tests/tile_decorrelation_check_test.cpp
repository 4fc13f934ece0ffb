// The tile_decorrelation check end to end on lavapipe: it fails on the bug it
// exists for (Bevy #24670, light tiles seeded by tile + frame, so each frame's
// pools are last frame's shifted by one tile:
// scenarios/bugs/bevy_24670_light_tiles_scroll.json), passes on the fix, and
// refuses a frame it cannot compare.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

const std::string kBug = "scenarios/bugs/bevy_24670_light_tiles_scroll.json";

nlohmann::json decorrelation(const std::filesystem::path& out) { return test::check_result(out, "tile_decorrelation"); }

TEST(TileDecorrelationCheck, FailsOnScrollingTilesAndPassesOnFreshOnes) {
  test::TempDir dir("tile_decorrelation");
  const std::string scenario = (test::source_dir() / kBug).string();
  const auto bug = test::run_giharness("run " + scenario + " --out " + (dir.path() / "bug").string());
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = decorrelation(dir.path() / "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  // Every tile but the last repeats a pool of the frame before exactly: 127 of 128.
  for (const auto& f : b.at("figures").at("judged_frames")) {
    EXPECT_EQ(f.at("max_share").get<double>(), 1.0);
    EXPECT_NEAR(f.at("mean_share").get<double>(), 127.0 / 128.0, 1e-9);
  }
  const auto fix = test::run_giharness("run " + scenario + " --set light_tiles.seeding=independent --out " +
                                       (dir.path() / "fix").string());
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json x = decorrelation(dir.path() / "fix");
  EXPECT_EQ(x.at("verdict"), "pass");
  EXPECT_EQ(x.at("figures").at("max_share").get<double>(), 0.0);
}

TEST(TileDecorrelationCheck, FrameZeroHasNothingToCompareWith) {
  test::TempDir dir("tile_decorrelation_bad");
  nlohmann::json doc = test::read_json(test::source_dir() / kBug);
  doc.erase("bug");
  doc["checks"] = {{{"name", "tile_decorrelation"}, {"frames", {0}}}};
  const std::filesystem::path file = dir.path() / "bad.json";
  std::ofstream(file) << doc.dump(1);
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/0/frames"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
