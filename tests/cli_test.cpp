// The command line as scripts see it: exit codes, messages, summary.json.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/test_support.h"

namespace gi {
namespace {

std::string bad(const std::string& name) {
  return (test::source_dir() / "tests/data/scenarios/bad" / name).string();
}

// Malformed scenarios exit 2 and the message names the file and the JSON path.
struct BadScenario {
  const char* file;
  const char* json_path;
};

class BadScenarioExitsTwo : public ::testing::TestWithParam<BadScenario> {};

TEST_P(BadScenarioExitsTwo, NamesFileAndPath) {
  test::TempDir out("bad");
  const test::CommandResult r =
      test::run_giharness("run " + bad(GetParam().file) + " --out " + out.path().string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(GetParam().file), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(GetParam().json_path), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "summary.json"));
}

INSTANTIATE_TEST_SUITE_P(Cli, BadScenarioExitsTwo,
                         ::testing::Values(BadScenario{"wrong_type.json", "/frames"},
                                           BadScenario{"unknown_event_type.json", "/events/3/type"},
                                           BadScenario{"missing_scene_file.json", "/scene/gltf"}));

TEST(Cli, MissingScenarioFileExitsTwo) {
  const test::CommandResult r = test::run_giharness("run /nonexistent/scenario.json");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/scenario.json"), std::string::npos);
}

// The message names the option, so a script's log says which flag is wrong.
TEST(Cli, UnknownOptionExitsTwo) {
  const test::CommandResult r = test::run_giharness("run --no-such-option x.json");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--no-such-option"), std::string::npos) << r.output;
}

// A small scenario file for the runs below (the real ones are 320x180).
std::filesystem::path write_small_cornell(const test::TempDir& dir, std::uint32_t frames) {
  const std::filesystem::path file = dir.path() / "small_cornell.json";
  std::ofstream(file) << R"({"name": "small_cornell", "scene": {"generator": "cornell_box"},
    "resolution": [48, 32], "frames": )" << frames
                      << R"(, "seed": 3, "mode": "reference", "samples_per_frame": 2,
    "checks": [{"name": "finite"}]})";
  return file;
}

TEST(Cli, RunWritesSummaryWithDeviceAndPassTimings) {
  test::TempDir dir("summary");
  const auto scenario = write_small_cornell(dir, 8);
  const test::CommandResult r =
      test::run_giharness("run " + scenario.string() + " --capture 7 --out " + (dir.path() / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = test::read_json(dir.path() / "out/summary.json");
  EXPECT_EQ(s["verdict"], "pass");
  for (const char* key : {"name", "driver_info", "mesa_version", "llvm_version", "subgroup_size", "lp_num_threads"})
    EXPECT_TRUE(s["device"].contains(key)) << key;
  // The default device (lavapipe when present) and the backend auto picks there.
  EXPECT_EQ(s["device"]["name"], test::device_support().name);
  EXPECT_EQ(s["device"]["backend"], test::device_support().auto_backend);
  const nlohmann::json& passes = s["timings"]["passes"];
  for (const char* pass : {"primary_visibility", "gbuffer_resolve", "reference_path_trace"}) {
    ASSERT_TRUE(passes.contains(pass)) << pass << " in " << passes.dump();
    EXPECT_EQ(passes[pass]["frames"], 8);
    EXPECT_GT(passes[pass]["mean_ms"].get<double>(), 0.0);
  }
  EXPECT_EQ(s["frames"].size(), 8u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "out/captures/frame_00007/images.exr"));
}

// --frames below the scenario's own capture frames: those captures are
// skipped with a note (summary.json skipped_captures), the run goes on; a
// --capture past the run is a command-line mistake (exit 2, naming it).
TEST(Cli, ShortRunSkipsTheScenariosLaterCapturesAndRefusesALateCaptureOption) {
  test::TempDir dir("short_captures");
  const std::filesystem::path file = dir.path() / "captured.json";
  std::ofstream(file) << R"({"name": "captured", "scene": {"generator": "cornell_box"},
    "resolution": [32, 24], "frames": 12, "seed": 3, "mode": "reference", "capture": [2, 10],
    "checks": [{"name": "finite"}]})";
  const test::CommandResult r =
      test::run_giharness("run " + file.string() + " --frames 5 --out " + (dir.path() / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("capture at frame 10 skipped"), std::string::npos) << r.output;
  const nlohmann::json s = test::read_json(dir.path() / "out/summary.json");
  EXPECT_EQ(s["skipped_captures"], nlohmann::json::array({10}));
  EXPECT_EQ(s["captures"].size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "out/captures/frame_00002/images.exr"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out/captures/frame_00010"));

  const test::CommandResult late = test::run_giharness("run " + file.string() + " --frames 5 --capture 7 --out " +
                                                       (dir.path() / "late").string());
  EXPECT_EQ(late.exit_code, 2) << late.output;
  EXPECT_NE(late.output.find("--capture"), std::string::npos) << late.output;
  EXPECT_NE(late.output.find("frame 7 is past the run's last frame 4"), std::string::npos) << late.output;
}

// Same scenario, seed and device: the same bits, also with one lavapipe thread
// (LP_NUM_THREADS means nothing to other drivers: there the runs simply repeat).
TEST(Cli, RunsAreBitIdenticalAcrossRunsAndThreadCounts) {
  test::TempDir dir("determinism");
  const auto scenario = write_small_cornell(dir, 6);
  auto run = [&](const std::string& name, const std::string& env) {
    const test::CommandResult r =
        test::run_giharness("run " + scenario.string() + " --out " + (dir.path() / name).string(), env);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return test::read_json(dir.path() / name / "summary.json")["final_image_hash"].get<std::string>();
  };
  const std::string a = run("a", "");
  EXPECT_EQ(a, run("b", ""));
  EXPECT_EQ(a, run("one_thread", "LP_NUM_THREADS=1"));
  EXPECT_EQ(a, run("four_threads", "LP_NUM_THREADS=4"));
}

TEST(Cli, ReferenceCommandWritesImageAndTiming) {
  test::TempDir dir("reference");
  const auto scenario = write_small_cornell(dir, 4);
  const test::CommandResult r = test::run_giharness(
      "reference " + scenario.string() + " --spp 8 --out " + (dir.path() / "ref").string(),
      "GIHARNESS_CACHE_DIR=" + (dir.path() / "cache").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = test::read_json(dir.path() / "ref/summary.json");
  EXPECT_EQ(s["spp"], 8);
  EXPECT_GT(s["rays"].get<std::uint64_t>(), 48u * 32u * 8u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "ref/reference.exr"));
}

}  // namespace
}  // namespace gi
