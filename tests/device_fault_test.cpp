// A GPU that stops answering ends a run with exit code 3 and a clear message,
// and a nightly marks the scenario device_error and goes on (its scenarios
// run in processes of their own); --resume runs those again. The timeout
// is forced with GIHARNESS_GPU_TIMEOUT_S=0: every submission that is still in
// flight when first polled counts as hung (lavapipe runs submissions on its
// own thread, so the first one to take any time trips it).
#include <gtest/gtest.h>

#include <fstream>

#include "tests/test_support.h"

namespace gi {
namespace {

TEST(DeviceFault, GpuTimeoutExitsThreeWithAClearMessage) {
  test::TempDir dir("gpu-timeout");
  const auto scenario = dir.path() / "s.json";
  std::ofstream(scenario) << R"({"name": "timeout", "scene": {"generator": "cornell_box"}, "resolution": [64, 64],
                                 "frames": 4, "mode": "reference"})";
  const test::CommandResult r = test::run_giharness(
      "run " + scenario.string() + " --out " + (dir.path() / "out").string(), "GIHARNESS_GPU_TIMEOUT_S=0");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("GPU timeout"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("GIHARNESS_GPU_TIMEOUT_S"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out/summary.json")) << "no result from a hung run";
}

TEST(DeviceFault, NightlyKeepsAValidReportAndMarksTheScenario) {
  test::TempDir dir("gpu-timeout-nightly");
  const auto out = dir.path() / "out";
  const test::CommandResult r = test::run_giharness(
      "nightly --suite " + (test::source_dir() / "tests/data/suites/tiny").string() + " --out " + out.string() +
          " --baseline " + (dir.path() / "none").string(),
      "GIHARNESS_GPU_TIMEOUT_S=0");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  const nlohmann::json suite = test::read_json(out / "summary.json");  // valid JSON
  // Each scenario runs in its own process: every one of them reaches the GPU
  // and times out, and each is marked; the night itself is not interrupted.
  EXPECT_FALSE(suite.value("interrupted", false));
  ASSERT_EQ(suite["scenarios"].size(), 3u) << suite.dump(1);
  for (const nlohmann::json& row : suite["scenarios"]) {
    EXPECT_EQ(row["status"], "complete");
    EXPECT_EQ(row["verdict"], "device_error") << row.dump(1);
    EXPECT_EQ(row["exit_code"], 3);
    EXPECT_NE(row.value("error", "").find("GPU timeout"), std::string::npos) << row.dump(1);
  }

  // Once the GPU answers again, --resume runs the device errors again.
  const test::CommandResult resumed = test::run_giharness(
      "nightly --suite " + (test::source_dir() / "tests/data/suites/tiny").string() + " --out " + out.string() +
      " --baseline " + (dir.path() / "none").string() + " --resume");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;  // the tiny suite passes
  const nlohmann::json done = test::read_json(out / "summary.json");
  EXPECT_FALSE(done.value("interrupted", false));
  ASSERT_EQ(done["scenarios"].size(), 3u) << done.dump(1);  // every scenario of tests/data/suites/tiny
  for (const nlohmann::json& row : done["scenarios"]) EXPECT_EQ(row["status"], "complete");
}

}  // namespace
}  // namespace gi
