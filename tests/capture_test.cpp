// Captures (replay/capture.h), `giharness replay --verify`, the determinism
// check and the nightly's failure captures (docs/design.md §6, §9), end to end on
// the default device at 64x48 (each run of 120 frames takes about a second
// on lavapipe).
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <xxhash.h>

#include <cstring>
#include <fstream>
#include <map>

#include "core/npy.h"
#include "core/scenario.h"
#include "replay/capture.h"
#include "checks/determinism_check.h"
#include "replay/run_scenario.h"
#include "tests/test_support.h"

namespace gi {
namespace {

// Realtime DI with a camera sweep over frames 10-90 and the light off over
// 64-79: the capture at 60 sits inside the sweep with the light on, and the
// replay crosses the light going off, coming back on and the sweep's end.
std::filesystem::path write_sweep_toggle(const std::filesystem::path& dir, const std::string& checks) {
  const std::filesystem::path file = dir / "sweep_toggle.json";
  std::ofstream(file) << R"({"name": "sweep_toggle", "scene": {"generator": "cornell_box"},
    "resolution": [64, 48], "frames": 120, "seed": 7, "mode": "realtime",
    "events": [
      {"type": "camera_sweep", "frames": [10, 90],
       "from": {"position": [0.278, 0.4, -1.2], "target": [0.278, 0.273, 0.28]},
       "to": {"position": [0.1, 0.273, -0.8], "target": [0.3, 0.273, 0.28]}},
      {"type": "light_off", "frame": 64, "light": "light"},
      {"type": "light_on", "frame": 80, "light": "light"}],
    "checks": )" << checks << "}";
  return file;
}

std::vector<nlohmann::json> read_lines(const std::filesystem::path& file) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

std::string hash_of(const nlohmann::json& record, const std::string& buffer) {
  for (const nlohmann::json& b : record["buffers"])
    if (b[0] == buffer) return b[1];
  return "";
}

// One 120-frame run with frame 60 captured, shared by the tests below.
class Capture60 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("capture60");
    const auto scenario = write_sweep_toggle(dir_->path(), R"([{"name": "finite"}])");
    const test::CommandResult r =
        test::run_giharness("run " + scenario.string() + " --capture 60 --out " + run_dir().string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::filesystem::path run_dir() { return dir_->path() / "run"; }
  static std::filesystem::path capture() { return run_dir() / "captures/frame_00060"; }
  static test::TempDir* dir_;
};
test::TempDir* Capture60::dir_ = nullptr;

TEST_F(Capture60, ReplayOfFrames61To119IsBitIdenticalInEveryBuffer) {
  // A run that hashes only for its capture logs from the captured frame on:
  // the frames a replay of the capture compares.
  std::map<std::uint32_t, nlohmann::json> original;
  for (const nlohmann::json& rec : read_lines(run_dir() / "buffer_hashes.jsonl")) original[rec["frame"]] = rec;
  ASSERT_EQ(original.size(), 60u);
  ASSERT_EQ(original.begin()->first, 60u);
  ASSERT_EQ(original.rbegin()->first, 119u);
  // The comparison means something only if the buffers change over frames.
  EXPECT_NE(hash_of(original[60], "di/output"), hash_of(original[61], "di/output"));
  EXPECT_NE(hash_of(original[60], "di/stored_reservoirs"), hash_of(original[61], "di/stored_reservoirs"));

  const auto out = dir_->path() / "replay";
  const test::CommandResult r =
      test::run_giharness("replay " + capture().string() + " --verify --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json verify = test::read_json(out / "verify.json");
  EXPECT_EQ(verify["verdict"], "identical");
  EXPECT_EQ(verify["frames_compared"], 60);  // the restored frame 60, then 61..119
  EXPECT_EQ(verify["divergent_frames"], 0);
  // Independently of the comparator: every replayed record equals the original's line.
  const auto replayed = read_lines(out / "buffer_hashes.jsonl");
  ASSERT_EQ(replayed.size(), 60u);
  std::size_t buffers = 0;
  for (const nlohmann::json& rec : replayed) {
    const std::uint32_t f = rec["frame"];
    EXPECT_EQ(rec["buffers"], original.at(f)["buffers"]) << "frame " << f;
    buffers += rec["buffers"].size();
  }
  EXPECT_EQ(buffers, 60u * original[60]["buffers"].size());
  EXPECT_EQ(test::read_json(out / "summary.json")["resumed_from"]["frame"], 60);
}

// One DI reservoir changed in the snapshot (the world cache does not exist
// yet; a cell will be the natural thing to perturb once it does).
TEST_F(Capture60, PerturbedReservoirIsCaughtByVerifyNamingFrameAndBuffer) {
  const auto copy = dir_->path() / "perturbed";
  std::filesystem::copy(capture(), copy);
  const auto file = copy / "di.stored_reservoirs.npy";
  NpyArray a = read_npy(file);
  ASSERT_EQ(a.shape, (std::vector<std::uint64_t>{1, 48, 64, 8}));
  // DiReservoir: light sample (4 words), M, W, pad, pad. Double W in the middle pixel.
  const std::size_t word = ((24 * 64 + 32) * 8) + 5;
  float w = 0;
  std::memcpy(&w, a.data.data() + word * 4, 4);
  ASSERT_GT(w, 0.0f) << "the middle pixel should hold a light sample";
  w = w * 2.0f + 1.0f;
  std::memcpy(a.data.data() + word * 4, &w, 4);
  write_npy(file, a.dtype, a.shape, a.data.data(), a.data.size());

  const auto out = dir_->path() / "replay_perturbed";
  const test::CommandResult r = test::run_giharness("replay " + copy.string() + " --verify --out " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("frame 60"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("di/stored_reservoirs"), std::string::npos) << r.output;
  const nlohmann::json verify = test::read_json(out / "verify.json");
  EXPECT_EQ(verify["first_divergent_frame"], 60);
  EXPECT_EQ(verify["first_divergent_buffers"], nlohmann::json::array({"di/stored_reservoirs"}));
  // It spreads through the replayed frames too (temporal reuse reads it at 61).
  EXPECT_GT(verify["divergent_frames"].get<int>(), 1);
}

// The issue's perturbation: one world-cache cell changed in a snapshot of a
// scenario that runs the cache (the closed room's light toggle, a 2^16-cell
// table as the cache tests use, captured at frame 30 of 40).
TEST(CaptureWorldCache, PerturbedCellIsCaughtByVerifyNamingFrameAndBuffer) {
  test::TempDir dir("capture-cache");
  const auto run = dir.path() / "run";
  const test::CommandResult original = test::run_giharness(
      "run " + (test::source_dir() / "scenarios/cache_light_toggle_closed_room.json").string() +
      " --set world_cache.cells=65536 --frames 40 --capture 30 --out " + run.string());
  // The lighting events lie past frame 40 and lag_limit is 90: blend_lag
  // judges nothing and says so (inconclusive, exit 1); the others pass.
  ASSERT_EQ(original.exit_code, 1) << original.output;
  EXPECT_NE(original.output.find("blend_lag inconclusive"), std::string::npos) << original.output;
  // Unperturbed, the cache's snapshot replays frames 30-39 bit for bit.
  const test::CommandResult same = test::run_giharness("replay " + (run / "captures/frame_00030").string() +
                                                       " --verify --out " + (dir.path() / "replay").string());
  EXPECT_EQ(same.exit_code, 0) << same.output;
  const auto copy = dir.path() / "perturbed";
  std::filesystem::copy(run / "captures/frame_00030", copy);
  const auto file = copy / "world_cache.radiance.npy";
  NpyArray a = read_npy(file);
  ASSERT_EQ(a.shape.size(), 2u);
  ASSERT_EQ(a.shape[1], 4u);
  // The first cell holding a sample: add to its red irradiance.
  std::size_t cell = a.shape[0];
  for (std::size_t c = 0; c < a.shape[0]; ++c) {
    float n = 0;
    std::memcpy(&n, a.data.data() + (c * 4 + 3) * 4, 4);
    if (n > 0.0f) { cell = c; break; }
  }
  ASSERT_LT(cell, a.shape[0]) << "no live cell in the snapshot";
  float r = 0;
  std::memcpy(&r, a.data.data() + cell * 16, 4);
  r = r * 2.0f + 1.0f;
  std::memcpy(a.data.data() + cell * 16, &r, 4);
  write_npy(file, a.dtype, a.shape, a.data.data(), a.data.size());

  const auto out = dir.path() / "replay_perturbed";
  const test::CommandResult v = test::run_giharness("replay " + copy.string() + " --verify --out " + out.string());
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find("frame 30"), std::string::npos) << v.output;
  EXPECT_NE(v.output.find("world_cache/radiance"), std::string::npos) << v.output;
  const nlohmann::json verify = test::read_json(out / "verify.json");
  EXPECT_EQ(verify["first_divergent_frame"], 30);
  EXPECT_EQ(verify["first_divergent_buffers"], nlohmann::json::array({"world_cache/radiance"}));
}

// A capture written before the GPU hashed (2026-12-03): its manifest has no
// hash_scheme and XXH3-64 hashes. It still restores (its files check
// against those hashes, no warning) and replays; --verify refuses it with
// a clear error, since its run_hashes.jsonl cannot be compared.
TEST_F(Capture60, AnXxh3CaptureReplaysAndRefusesVerify) {
  const auto copy = dir_->path() / "legacy";
  std::filesystem::copy(capture(), copy);
  nlohmann::json m = test::read_json(copy / "manifest.json");
  EXPECT_EQ(m["hash_scheme"], "gi-word-hash-v1");
  m.erase("hash_scheme");
  for (nlohmann::json& b : m["buffers"]) {
    const NpyArray a = read_npy(copy / b["file"].get<std::string>());
    b["hash"] = fmt::format("{:016x}", XXH3_64bits(a.data.data(), a.data.size()));
  }
  std::ofstream(copy / "manifest.json") << m.dump(1);
  const test::CommandResult replay = test::run_giharness("replay " + copy.string() + " --frames 64 --out " +
                                                         (dir_->path() / "legacy_replay").string());
  // The capture's scenario holds the finite check alone, which its run passed:
  // the legacy replay restores the same state, so the check passes again.
  EXPECT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_EQ(test::check_result(dir_->path() / "legacy_replay", "finite").value("verdict", ""), "pass");
  EXPECT_EQ(replay.output.find("bytes differ"), std::string::npos) << replay.output;
  const test::CommandResult verify =
      test::run_giharness("replay " + copy.string() + " --verify --out " + (dir_->path() / "legacy_verify").string());
  EXPECT_EQ(verify.exit_code, 2) << verify.output;
  EXPECT_NE(verify.output.find("xxh3-64"), std::string::npos) << verify.output;
  EXPECT_NE(verify.output.find("/hash_scheme"), std::string::npos) << verify.output;
}

TEST_F(Capture60, EveryNpyHeaderMatchesTheManifest) {
  const nlohmann::json m = test::read_json(capture() / "manifest.json");
  EXPECT_EQ(m["frame"], 60);
  EXPECT_EQ(m["seed"], 7);
  EXPECT_EQ(m["backend"], test::device_support().auto_backend);  // bvh on lavapipe and without ray queries
  ASSERT_GE(m["buffers"].size(), 7u);
  for (const nlohmann::json& b : m["buffers"]) {
    const auto file = capture() / b["file"].get<std::string>();
    const NpyArray header = read_npy_header(file);
    EXPECT_EQ(header.dtype, b["dtype"]) << b["name"];
    EXPECT_EQ(nlohmann::json(header.shape), b["shape"]) << b["name"];
    const NpyArray a = read_npy(file);
    EXPECT_EQ(a.data.size(), b["bytes"].get<std::size_t>()) << b["name"];
    EXPECT_EQ(bytes_hash(a.data.data(), a.data.size()), b["hash"]) << b["name"];
  }
  EXPECT_TRUE(std::filesystem::exists(capture() / "run_hashes.jsonl"));
}

TEST_F(Capture60, ExrLayersListWithExrheader) {
  const test::CommandResult r = test::run_command("exrheader " + (capture() / "images.exr").string());
  ASSERT_EQ(r.exit_code, 0) << "exrheader (Debian package openexr, in .ci/setup): " << r.output;
  for (const char* channel : {"    R,", "di.R,", "albedo.R,", "normal.R,", "depth.R,", "motion.R,", "half_a.R,"})
    EXPECT_NE(r.output.find(channel), std::string::npos) << channel << " in\n" << r.output;
}

TEST(Capture, ReplayOfAFolderWithoutManifestIsBadInput) {
  test::TempDir dir("no_manifest");
  const test::CommandResult r = test::run_giharness("replay " + dir.path().string() + " --verify");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("manifest.json"), std::string::npos) << r.output;
}

// The comparator on its own: the first divergent frame, in list order.
TEST(HashLogs, FirstDivergentFrameAndBuffersAreNamed) {
  test::TempDir dir("hash_logs");
  auto write = [&](const char* name, const std::vector<std::string>& frames) {
    std::ofstream out(dir.path() / name);
    for (const std::string& f : frames) out << f << "\n";
  };
  write("a.jsonl", {R"({"frame": 3, "buffers": [["x", "1"], ["y", "2"]]})",
                    R"({"frame": 4, "buffers": [["x", "1"], ["y", "2"]]})",
                    R"({"frame": 5, "buffers": [["x", "1"], ["y", "2"]]})"});
  write("b.jsonl", {R"({"frame": 4, "buffers": [["x", "1"], ["y", "2"]]})",
                    R"({"frame": 5, "buffers": [["x", "9"], ["z", "2"]]})",
                    R"({"frame": 6, "buffers": [["x", "1"]]})"});
  const HashLogComparison c = compare_hash_logs(dir.path() / "a.jsonl", dir.path() / "b.jsonl");
  EXPECT_EQ(c.frames_compared, 2u);
  EXPECT_EQ(c.divergent_frames, 1u);
  EXPECT_EQ(c.unmatched_frames, 1u);
  ASSERT_TRUE(c.first);
  EXPECT_EQ(c.first->frame, 5u);
  EXPECT_EQ(c.first->buffers,
            (std::vector<std::string>{"x", "z (missing in the original)", "y (missing in the candidate)"}));
  EXPECT_FALSE(c.identical());
  EXPECT_TRUE(compare_hash_logs(dir.path() / "a.jsonl", dir.path() / "a.jsonl").identical());
}

// The scenario check: a second run and a replay from the snapshot at frame
// 59 (the default, frames / 2 − 1), both compared with the main run.
TEST(Determinism, CheckPassesOnTheSweepAndToggleScenario) {
  test::TempDir dir("determinism_check");
  const auto scenario = write_sweep_toggle(dir.path(), R"([{"name": "determinism"}])");
  const auto out = dir.path() / "out";
  const test::CommandResult r = test::run_giharness("run " + scenario.string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = test::read_json(out / "summary.json");
  const nlohmann::json& c = s["checks"][0];
  EXPECT_EQ(c["name"], "determinism");
  EXPECT_EQ(c["verdict"], "pass") << c.dump(2);
  EXPECT_EQ(c["figures"]["second_run"]["frames_compared"], 120);
  EXPECT_EQ(c["figures"]["replay"]["frames_compared"], 61);  // restored 59, then 60..119
  EXPECT_TRUE(std::filesystem::exists(out / "captures/frame_00059/manifest.json"));
}

// The check fires: when the main run's bits differ from a repeat's (here the
// main run's log is altered at frame 70, as a non-deterministic pass would
// leave it), both the second run and the replay name frame 70 and the buffer.
TEST(Determinism, CheckFailsNamingTheFirstDivergentFrameAndBuffer) {
  test::TempDir dir("determinism_fires");
  const Scenario scenario = load_scenario(write_sweep_toggle(dir.path(), R"([{"name": "determinism"}])"));
  RunOptions options;
  options.out_dir = dir.path() / "out";
  options.quiet = true;
  ASSERT_EQ(run_scenario(scenario, options).exit_code, 0);
  const auto log = options.out_dir / "buffer_hashes.jsonl";
  std::vector<nlohmann::json> lines = read_lines(log);
  for (nlohmann::json& b : lines.at(70)["buffers"])
    if (b[0] == "di/output") b[1] = "0000000000000000";
  {
    std::ofstream out(log);
    for (const nlohmann::json& l : lines) out << l.dump() << "\n";
  }
  const DeterminismParams params = determinism_params(*scenario.find_check("determinism"), scenario, 120);
  const CheckResult c = judge_determinism(options.out_dir, params);  // the main run left its reruns beside it
  EXPECT_EQ(c.verdict, Verdict::fail) << c.message;
  EXPECT_EQ(c.first_failing_frame, 70u);
  for (const char* run : {"second_run", "replay"}) {
    EXPECT_EQ(c.figures[run]["first_divergent_frame"], 70) << run;
    EXPECT_EQ(c.figures[run]["first_divergent_buffers"], nlohmann::json::array({"di/output"})) << run;
    EXPECT_EQ(c.figures[run]["divergent_frames"], 1) << run;
  }
}

// A failing check in a nightly leaves a capture of its first failing frame.
TEST(NightlyCapture, FailingCheckLeavesACaptureOfItsFirstFailingFrame) {
  test::TempDir dir("nightly_failure_capture");
  std::filesystem::create_directories(dir.path() / "suite");
  // relMSE must be ≤ 0 × noise: fails at frame 5 (the only compared frame).
  std::ofstream(dir.path() / "suite/tiny_fail.json")
      << R"({"name": "tiny_fail", "scene": {"generator": "cornell_box"}, "resolution": [32, 24], "frames": 8,
        "seed": 3, "mode": "reference", "samples_per_frame": 1,
        "checks": [{"name": "reference", "frames": [5], "spp": 16, "relmse_noise_factor": 0.0}]})";
  const auto out = dir.path() / "night";
  const test::CommandResult r = test::run_giharness("nightly --suite " + (dir.path() / "suite").string() + " --out " +
                                                    out.string() + " --baseline " + (dir.path() / "none").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const nlohmann::json s = test::read_json(out / "tiny_fail/summary.json");
  ASSERT_EQ(s["checks"][0]["verdict"], "fail");
  ASSERT_EQ(s["checks"][0]["first_failing_frame"], 5);
  ASSERT_EQ(s["failure_captures"].size(), 1u);
  EXPECT_EQ(s["failure_captures"][0]["frame"], 5);
  const auto capture = out / "tiny_fail/captures/frame_00005";
  EXPECT_EQ(test::read_json(capture / "manifest.json")["frame"], 5);
  EXPECT_TRUE(std::filesystem::exists(capture / "images.exr"));
  EXPECT_FALSE(std::filesystem::exists(out / "tiny_fail/.failure_rerun"));
  const nlohmann::json suite = test::read_json(out / "summary.json");
  EXPECT_EQ(suite["scenarios"][0]["failure_captures"][0]["capture"], "tiny_fail/captures/frame_00005");
  // The nightly inspected it (giharness inspect), and the report links the page.
  EXPECT_TRUE(std::filesystem::exists(capture / "inspect.html"));
  EXPECT_EQ(suite["scenarios"][0]["failure_captures"][0]["inspect"], "tiny_fail/captures/frame_00005/inspect.html");
  EXPECT_NE(test::read_text(out / "report.html").find("href=\"tiny_fail/captures/frame_00005/inspect.html#source=output\""),
            std::string::npos);
  // …and it replays to the same bits as the run that captured it.
  const test::CommandResult replay = test::run_giharness("replay " + capture.string() + " --verify --out " +
                                                         (dir.path() / "replay").string());
  EXPECT_EQ(replay.exit_code, 0) << replay.output;
}

}  // namespace
}  // namespace gi
