// The cache_integrity check end to end on lavapipe: it fails on the bug it
// exists for (Bevy #21953: the jittered query point quantized at the
// unjittered point's LOD, scenarios/bugs/bevy_21953_jitter_keeps_the_lod.json),
// passes on the fix and on every release profile's cache (0.17's re-hash
// probing, 0.18, 0.19's stochastic LOD, jitter and first-bounce rule), says
// inconclusive when the camera moved, and refuses bad frames.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

const std::string kBug = "scenarios/bugs/bevy_21953_jitter_keeps_the_lod.json";

nlohmann::json integrity_result(const test::TempDir& dir, const std::string& tag) {
  const nlohmann::json summary = test::read_json(dir.path() / tag / "summary.json");
  for (const auto& c : summary.at("checks"))
    if (c.at("name") == "cache_integrity") return c;
  ADD_FAILURE() << "no cache_integrity result";
  return {};
}

test::CommandResult run(const test::TempDir& dir, const std::string& scenario, const std::string& sets,
                        const std::string& tag) {
  return test::run_giharness("run " + scenario + " --set world_cache.cells=262144 " + sets + " --out " +
                             (dir.path() / tag).string());
}

// The museum scenario over the open field as a release profile ships it (no
// overrides, no bug), with its own camera keys and checks.
nlohmann::json open_field(const std::string& name, int frames, const nlohmann::json& keys,
                          const nlohmann::json& checks) {
  nlohmann::json doc = test::read_json(test::source_dir() / kBug);
  doc.erase("bug");
  doc.erase("overrides");
  doc["name"] = name;
  doc["frames"] = frames;
  doc["events"][0]["keys"] = keys;
  doc["checks"] = checks;
  return doc;
}

nlohmann::json key(int frame, double x, double tx, double tz) {
  return {{"frame", frame}, {"position", {x, 2.0, 3.0}}, {"target", {tx, 0.0, tz}}};
}

TEST(CacheIntegrityCheck, FailsOnTheJitterThatKeepsItsLodAndPassesOnTheFix) {
  test::TempDir dir("cache_integrity_bug");
  const std::string scenario = (test::source_dir() / kBug).string();
  const auto bug = run(dir, scenario, "", "bug");
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = integrity_result(dir, "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  std::uint32_t miskeyed = 0;
  for (const auto& f : b.at("figures").at("judged_frames")) miskeyed += f.at("miskeyed").get<std::uint32_t>();
  EXPECT_GT(miskeyed, 20u) << b.dump(1);

  const auto fix = run(dir, scenario, "--set world_cache.jitter_lod=redrawn", "fix");
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json x = integrity_result(dir, "fix");
  EXPECT_EQ(x.at("verdict"), "pass") << x.dump(1);
  for (const auto& f : x.at("figures").at("judged_frames")) {
    EXPECT_EQ(f.at("live"), f.at("stats_live"));
    EXPECT_GT(f.at("live").get<std::uint32_t>(), 1000u);
  }
}

// The open field as the release profiles ship it (no scenario overrides):
// the camera turns but stays put, so every judged frame is testable.
TEST(CacheIntegrityCheck, PassesOnEveryReleaseProfile) {
  test::TempDir dir("cache_integrity_profiles");
  const nlohmann::json doc =
      open_field("cache_integrity_profiles", 24, {key(0, 3.0, 40.0, 60.0), key(23, 3.0, -40.0, -60.0)},
                 {{{"name", "cache_integrity"}, {"frames", {12, 23}}}});
  const std::filesystem::path file = dir.path() / "scenario.json";
  std::ofstream(file) << doc.dump(1);
  for (const char* profile : {"solari-0.17", "solari-0.18", "solari-0.19"}) {
    const auto r = run(dir, file.string(), std::string("--profile ") + profile, profile);
    EXPECT_EQ(r.exit_code, 0) << profile << "\n" << r.output;
    const nlohmann::json c = integrity_result(dir, profile);
    EXPECT_EQ(c.at("verdict"), "pass") << profile << " " << c.dump(1);
    EXPECT_EQ(c.at("figures").at("tested_frames"), 2) << profile;
  }
}

TEST(CacheIntegrityCheck, AMovedCameraIsInconclusiveAndBadFramesAreRefused) {
  test::TempDir dir("cache_integrity_moved");
  nlohmann::json doc = open_field("cache_integrity_moved", 8, {key(0, 3.0, 40.0, 60.0), key(4, 6.0, 40.0, 60.0)},
                                  {{{"name", "cache_integrity"}, {"frames", {7}}}});
  const std::filesystem::path file = dir.path() / "moved.json";
  std::ofstream(file) << doc.dump(1);
  run(dir, file.string(), "", "moved");
  const nlohmann::json c = integrity_result(dir, "moved");
  EXPECT_EQ(c.at("verdict"), "inconclusive") << c.dump(1);

  doc["checks"] = {{{"name", "cache_integrity"}, {"frames", {8}}}};
  const std::filesystem::path bad = dir.path() / "bad.json";
  std::ofstream(bad) << doc.dump(1);
  const auto r = run(dir, bad.string(), "", "bad");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/0/frames"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
