// The timing verdict end to end on the device: a baseline taken
// with the calibration kernel, then the same scenario with one pass really
// slowed (GIHARNESS_TEST_SLOW_PASS repeats its dispatch): the nightly names
// that pass, leaves the correctness verdict and the bits alone, and sets exit
// bit 4 only because --fail-on-timing asks it to.
#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

const nlohmann::json* timing_series(const nlohmann::json& row, const std::string& name) {
  for (const nlohmann::json& s : row["timing"]["series"])
    if (s["name"] == name) return &s;
  return nullptr;
}

TEST(TimingNightly, ASlowedPassIsNamedAndOnlyTheTimingBitIsSet) {
  const test::TempDir dir("timing-nightly");
  const std::filesystem::path suite = dir.path() / "suite", baselines = dir.path() / "baselines";
  std::filesystem::create_directories(suite);
  // Realtime DI (light tiles, ReSTIR DI) on the Cornell box, 40 frames.
  test::write_scenario_variant("scenarios/di_cornell_box.json", suite, "timed_di.json", [](nlohmann::json& s) {
    s["name"] = "timed_di";
    s["resolution"] = {48, 48};
    s["frames"] = 40;
    s["checks"] = nlohmann::json::array({{{"name", "finite"}}});
  });
  auto nightly = [&](const std::string& out, const std::string& flags, const std::string& env) {
    return test::run_giharness("nightly --suite " + suite.string() + " --out " + (dir.path() / out).string() +
                                   " --baseline " + baselines.string() + " " + flags,
                               env);
  };
  const std::string history = " --history " + (dir.path() / "history").string();
  const test::CommandResult base = nightly("base", "--update-baseline" + history, "");
  ASSERT_EQ(base.exit_code, 0) << base.output;
  // The one device class folder the run wrote (lavapipe: llvmpipe-<threads>threads).
  std::filesystem::path class_dir;
  for (const auto& entry : std::filesystem::directory_iterator(baselines)) class_dir = entry.path();
  ASSERT_TRUE(std::filesystem::exists(class_dir / "timed_di.json")) << base.output;
  const nlohmann::json baseline = test::read_json(class_dir / "timed_di.json");
  if (baseline["device"].value("device_type", "") != "cpu") GTEST_SKIP() << "calibrated samples are a CPU device's";
  ASSERT_TRUE(baseline.contains("timing_samples")) << baseline.dump(1).substr(0, 2000);
  EXPECT_EQ(baseline["timing_samples"]["unit"], "calibration");
  EXPECT_GT(baseline["timing_samples"]["calibration_ms"].get<double>(), 0.0);
  // Frame 0 is left out, and any frame that waited for a CPU (another job
  // on the machine) more than kMaxFrameWaitShare of the time it wanted one.
  const nlohmann::json& load = baseline["timing_samples"]["load"];
  EXPECT_EQ(load["frames"], 39) << load.dump();
  // ctest runs this test alone (tests/CMakeLists.txt); a machine loaded by
  // something else cannot judge timing, and the nightly says so: skipped then.
  if (39 - load["loaded_frames"].get<int>() < 8) GTEST_SKIP() << "the machine is loaded: " << load.dump();
  EXPECT_EQ(baseline["timing_samples"]["series"]["light_tiles"].size(), 39u - load["loaded_frames"].get<std::size_t>());

  // A second run of the unchanged tree adds its medians to the baseline:
  // the run-to-run spread the verdict allows for.
  const test::CommandResult again = nightly("again", "--add-timing-run", "");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const nlohmann::json again_timing = test::read_json(dir.path() / "again/summary.json")["scenarios"][0]["timing"];
  if (again_timing.value("reason", "").find("loaded") != std::string::npos)
    GTEST_SKIP() << "the machine is loaded: " << again_timing["reason"];
  EXPECT_EQ(test::read_json(dir.path() / "again/summary.json")["scenarios"][0].value("timing_run_added", false), true)
      << again.output;
  const nlohmann::json runs = test::read_json(class_dir / "timed_di.json")["timing_samples"]["other_runs"];
  ASSERT_EQ(runs.size(), 1u) << runs.dump();
  EXPECT_GT(runs[0]["median"]["light_tiles"].get<double>(), 0.0);
  EXPECT_GT(runs[0]["median_ms"]["light_tiles"].get<double>(), 0.0);

  const test::CommandResult slow =
      nightly("slow", "--fail-on-timing" + history, "GIHARNESS_TEST_SLOW_PASS=light_tiles:3");
  EXPECT_EQ(slow.exit_code, 4) << slow.output;
  const nlohmann::json summary = test::read_json(dir.path() / "slow/summary.json");
  const nlohmann::json& row = summary["scenarios"][0];
  EXPECT_EQ(row["verdict"], "pass") << row.dump(1);
  EXPECT_EQ(row["regressions"].size(), 0u) << row["regressions"].dump(1);
  // light_tiles only writes what it reads from elsewhere: three times over, the same bits.
  EXPECT_EQ(row["change"]["status"], "unchanged") << row["change"].dump(1);
  const nlohmann::json* tiles = timing_series(row, "light_tiles");
  ASSERT_NE(tiles, nullptr) << row["timing"].dump(1);
  EXPECT_EQ((*tiles)["verdict"], "regressed") << tiles->dump(1);
  EXPECT_GT((*tiles)["interval"][0].get<double>(), 1.25) << tiles->dump(1);
  EXPECT_EQ((*tiles)["baseline_runs"], 2) << tiles->dump(1);
  // Flagged, the scenario ran once more, and the slowdown repeated.
  EXPECT_EQ(row["timing"].value("confirmed_by_second_run", false), true) << row["timing"].dump(1);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "slow/timed_di/timing-confirm/timed_di/summary.json"));
  EXPECT_EQ(summary["verdict"], "timing_regressed");
  EXPECT_NE(test::read_text(dir.path() / "slow/junit.xml").find("timing regressed (--fail-on-timing): light_tiles"),
            std::string::npos);
  const std::string report = test::read_text(dir.path() / "slow/report.html");
  EXPECT_NE(report.find("Timing against the baseline"), std::string::npos);
  // The history: the base night's entry drawn as the trend, and now both nights kept.
  EXPECT_NE(report.find("Trend over the last 1 nights"), std::string::npos);
  std::size_t nights = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path() / "history")) nights += entry.path().extension() == ".json";
  EXPECT_EQ(nights, 2u);
}

TEST(TimingNightly, AMalformedSlowdownIsBadInput) {
  const test::TempDir dir("timing-slow-bad");
  const test::CommandResult r =
      test::run_giharness("run " + (test::source_dir() / "tests/data/suites/tiny/tiny_no_blocks.json").string() +
                              " --out " + dir.path().string(),
                          "GIHARNESS_TEST_SLOW_PASS=light_tiles:fast");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("GIHARNESS_TEST_SLOW_PASS"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
