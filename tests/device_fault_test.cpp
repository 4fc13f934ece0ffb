// A GPU that stops answering ends a run with exit code 3 and a clear message,
// and a nightly keeps its report valid with the scenario marked. The timeout
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
  EXPECT_TRUE(suite.value("interrupted", false));
  const nlohmann::json& first = suite["scenarios"][0];
  EXPECT_EQ(first["status"], "device_error");
  EXPECT_NE(first["error"].get<std::string>().find("GPU timeout"), std::string::npos);

  // Once the GPU answers again, --resume finishes the night.
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
