// Every change visible (reports/change.h): against an exact baseline (same
// device class, device and driver) a run is unchanged, changed (where, by how
// much, with a heat map) or, from anywhere else, without an exact baseline.
// The end-to-end tests run the tiny suite and a small realtime scenario on
// lavapipe; the rest are in process on synthetic images and documents.
#include <gtest/gtest.h>

#include <fstream>

#include "core/exr_io.h"
#include "app/sweep_plan.h"
#include "reports/baseline_store.h"
#include "reports/change.h"
#include "tests/test_support.h"

namespace gi {
namespace {

// The tiny suite plus the realtime Cornell box, each scenario optionally
// changed by one --vary-style setting.
std::filesystem::path make_suite(const std::filesystem::path& dir, const std::string& setting = "") {
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> files = {test::source_dir() / "tests/data/suites/change/realtime_cornell.json"};
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() / "tests/data/suites/tiny"))
    files.push_back(entry.path());
  for (const std::filesystem::path& file : files) {
    nlohmann::json doc = test::read_json(file);
    if (!setting.empty() && doc.value("mode", "") == "realtime")
      doc = sweep_points(doc, {parse_sweep_axis(setting)}).at(0).document;
    std::ofstream(dir / file.filename()) << doc.dump(2);
  }
  return dir;
}

const nlohmann::json& row_named(const nlohmann::json& suite, const std::string& name) {
  for (const nlohmann::json& row : suite["scenarios"])
    if (row.value("name", "") == name) return row;
  throw std::runtime_error("no row " + name);
}

// One baseline for every end-to-end test here: written once, timings
// ignored (they jitter on a shared machine; report_regression_test covers them).
class ChangeDetection : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("change");
    const std::filesystem::path suite = make_suite(dir_->path() / "suite");
    const test::CommandResult r = test::run_giharness("nightly --suite " + suite.string() + " --out " +
                                                      (dir_->path() / "first").string() + " --baseline " +
                                                      baselines().string() + " --update-baseline");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const auto& entry : std::filesystem::directory_iterator(baselines()))
      std::ofstream(entry.path() / "tolerances.json") << R"([{"pattern": "timings/*", "kind": "ignore"}])";
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::filesystem::path baselines() { return dir_->path() / "baselines"; }
  static test::TempDir* dir_;
};
test::TempDir* ChangeDetection::dir_ = nullptr;

TEST_F(ChangeDetection, UnchangedTreeIsUnchangedForEveryScenario) {
  const std::filesystem::path out = dir_->path() / "again";
  const test::CommandResult r = test::run_giharness("nightly --suite " + (dir_->path() / "suite").string() + " --out " +
                                                    out.string() + " --baseline " + baselines().string() +
                                                    " --fail-on-change");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json suite = test::read_json(out / "summary.json");
  ASSERT_EQ(suite["scenarios"].size(), 4u);
  for (const nlohmann::json& row : suite["scenarios"]) {
    EXPECT_EQ(row["change"]["status"], "unchanged") << row.dump(2);
    EXPECT_GT(row["change"]["frames_compared"].get<int>(), 0);
    EXPECT_GT(row["change"]["buffers_compared"].get<int>(), 0);
  }
  EXPECT_EQ(suite["changes"]["unchanged"], 4);
  EXPECT_NE(test::read_text(out / "junit.xml").find("<property name=\"change\" value=\"unchanged\"/>"), std::string::npos);
}

// The seeded change: ReSTIR DI's confidence cap 20 → 19 moves the realtime
// image's energy by far less than any tolerance, and no check fails.
TEST_F(ChangeDetection, NudgedProfileValueIsChangedWithFrameBuffersAndHeatMap) {
  const std::filesystem::path suite = make_suite(dir_->path() / "nudged", "restir_di.confidence_cap=19");
  const std::filesystem::path out = dir_->path() / "nudged_out";
  const std::string args =
      "nightly --suite " + suite.string() + " --baseline " + baselines().string() + " --out ";
  const test::CommandResult r = test::run_giharness(args + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;  // a change is not a failure by default
  const nlohmann::json summary = test::read_json(out / "summary.json");
  EXPECT_EQ(summary["changes"]["changed"], 1);
  EXPECT_EQ(summary["changes"]["unchanged"], 3);  // the reference-mode scenarios have no such value
  const nlohmann::json& row = row_named(summary, "realtime_cornell");
  EXPECT_EQ(row["verdict"], "pass");
  EXPECT_TRUE(row["regressions"].empty()) << row["regressions"].dump(2);
  const nlohmann::json& c = row["change"];
  ASSERT_EQ(c["status"], "changed") << c.dump(2);
  ASSERT_TRUE(c["first_differing_frame"].is_number()) << c.dump(2);
  EXPECT_LT(c["first_differing_frame"].get<int>(), 8);
  EXPECT_NE(std::find(c["differing_buffers"].begin(), c["differing_buffers"].end(), "di/output"),
            c["differing_buffers"].end())
      << c.dump(2);
  ASSERT_TRUE(c["image"].is_object()) << c.dump(2);
  EXPECT_GT(c["image"]["relmse"].get<double>(), 0.0);
  EXPECT_LT(std::abs(c["image"]["energy_ratio"].get<double>() - 1.0), 0.005);
  EXPECT_GT(c["image"]["pixels_differing"].get<int>(), 0);
  for (const char* image : {"baseline", "current", "difference"})
    EXPECT_TRUE(std::filesystem::exists(out / c["images"][image].get<std::string>())) << image;
  const std::string report = test::read_text(out / "report.html");
  EXPECT_NE(report.find("Bits against the exact baseline"), std::string::npos);
  EXPECT_NE(report.find("|Δ luminance|, white at"), std::string::npos);
  const std::string junit = test::read_text(out / "junit.xml");
  EXPECT_NE(junit.find("<property name=\"change\" value=\"changed\"/>"), std::string::npos);
  EXPECT_NE(junit.find("<property name=\"change_relmse\""), std::string::npos);

  // --fail-on-change: the same run fails, in the exit code, the row and JUnit.
  const std::filesystem::path strict = dir_->path() / "nudged_strict";
  const test::CommandResult f = test::run_giharness(args + strict.string() + " --fail-on-change");
  EXPECT_EQ(f.exit_code, 1) << f.output;
  EXPECT_EQ(row_named(test::read_json(strict / "summary.json"), "realtime_cornell")["verdict"], "changed");
  EXPECT_NE(test::read_text(strict / "junit.xml").find("changed against the exact baseline (--fail-on-change)"), std::string::npos);
}

// --- in process ---

Image gradient(float scale) {
  Image image(8, 4);
  for (std::uint32_t y = 0; y < 4; ++y)
    for (std::uint32_t x = 0; x < 8; ++x) image.at(x, y) = glm::vec3(0.1f * float(x + 1), 0.2f, 0.05f * float(y)) * scale;
  return image;
}

nlohmann::json device(const std::string& driver) {
  return {{"name", "llvmpipe (LLVM 15.0.6, 256 bits)"}, {"driver_info", driver}, {"lp_num_threads", "2"}};
}

nlohmann::json summary_with(const nlohmann::json& dev, const std::string& image_hash, const std::string& buffer_hash) {
  return {{"device", dev},
          {"resolved", {{"backend", "bvh"}}},
          {"final_image_hash", image_hash},
          {"final_image", kFinalImageFile},
          {"hashes", {{"scheme", "gi-word-hash-v1"}, {"first_frame", 0}, {"frame_images", {"a", "b", image_hash}}, {"final_buffers", {{"di/output", buffer_hash}}}}}};
}

TEST(ChangeDetectionUnit, ImageDifferenceMeasuresOnlyWhatDiffers) {
  const Image a = gradient(1.0f);
  const ImageDifference same = image_difference(a, a);
  EXPECT_EQ(same.relmse, 0.0);
  EXPECT_EQ(same.pixels_differing, 0u);
  EXPECT_EQ(same.energy_ratio, 1.0);
  Image b = a;
  b.at(3, 2) += glm::vec3(0.5f, 0.0f, 0.0f);
  const ImageDifference one = image_difference(a, b);
  EXPECT_EQ(one.pixels_differing, 1u);
  EXPECT_FLOAT_EQ(float(one.max_abs), 0.5f);
  EXPECT_GT(one.relmse, 0.0);
  EXPECT_GT(one.energy_ratio, 1.0);
  EXPECT_THROW(image_difference(a, Image(2, 2)), std::invalid_argument);
}

TEST(ChangeDetectionUnit, OnlyAnExactBaselineJudgesBits) {
  test::TempDir dir("change-unit");
  const nlohmann::json run = summary_with(device("Mesa 25.0.7"), "c", "x");
  ChangeInputs in{std::nullopt, dir.path() / "none.exr", run, dir.path(), dir.path() / "ev", "ev"};
  EXPECT_EQ(detect_change(in)["status"], "no_exact_baseline");  // no baseline at all

  nlohmann::json base = summary_with(device("Mesa 24.2.8"), "c", "x");
  in.baseline = base;
  nlohmann::json c = detect_change(in);
  EXPECT_EQ(c["status"], "no_exact_baseline");  // another driver: its bits say nothing here
  EXPECT_NE(c["reason"].get<std::string>().find("driver_info"), std::string::npos) << c.dump();

  base["device"]["lp_num_threads"] = "4";
  in.baseline = base;
  EXPECT_NE(detect_change(in)["reason"].get<std::string>().find("device class"), std::string::npos);

  base = summary_with(device("Mesa 25.0.7"), "c", "x");
  base.erase("hashes");  // written before hashes were kept
  in.baseline = base;
  c = detect_change(in);
  EXPECT_EQ(c["status"], "no_exact_baseline");
  EXPECT_NE(c["reason"].get<std::string>().find("baseline keeps no hashes"), std::string::npos) << c.dump();
  ChangeInputs cpu_only = in;  // a run with no GPU pipeline has nothing exact to compare
  cpu_only.baseline = summary_with(device("Mesa 25.0.7"), "c", "x");
  cpu_only.summary.erase("hashes");
  EXPECT_NE(detect_change(cpu_only)["reason"].get<std::string>().find("records no image"), std::string::npos);

  // Hashes of another scheme (XXH3 before hashing moved to the GPU).
  base = summary_with(device("Mesa 25.0.7"), "c", "x");
  base["hashes"]["scheme"] = "xxh3-64";
  in.baseline = base;
  c = detect_change(in);
  EXPECT_EQ(c["status"], "no_exact_baseline");
  EXPECT_NE(c["reason"].get<std::string>().find("xxh3-64"), std::string::npos) << c.dump();

  in.baseline = summary_with(device("Mesa 25.0.7"), "c", "x");
  EXPECT_EQ(detect_change(in)["status"], "unchanged");
  in.baseline = summary_with(device("Mesa 25.0.7"), "c", "y");  // only a buffer differs
  c = detect_change(in);
  EXPECT_EQ(c["status"], "changed");
  EXPECT_TRUE(c["first_differing_frame"].is_null());
  EXPECT_EQ(c["differing_buffers"], nlohmann::json::array({"di/output"}));
  EXPECT_NE(c["image_note"].get<std::string>().find("no image"), std::string::npos);
}

TEST(ChangeDetectionUnit, ChangedImageGetsFiguresAndThreePngs) {
  test::TempDir dir("change-images");
  const Image a = gradient(1.0f), b = gradient(1.002f);
  write_exr(dir.path() / "base.exr", {{"", &a}}, ExrPixels::half);
  write_exr(dir.path() / kFinalImageFile, {{"", &b}}, ExrPixels::half);
  ChangeInputs in{summary_with(device("d"), "c", "x"), dir.path() / "base.exr", summary_with(device("d"), "d", "x"),
                  dir.path(), dir.path() / "ev", "ev"};
  const nlohmann::json c = detect_change(in);
  ASSERT_EQ(c["status"], "changed");
  EXPECT_EQ(c["first_differing_frame"], 2);
  EXPECT_TRUE(c["differing_buffers"].empty());
  ASSERT_TRUE(c["image"].is_object()) << c.dump(2);
  EXPECT_NEAR(c["image"]["energy_ratio"].get<double>(), 1.002, 5e-4);  // half floats: 11 significant bits
  for (const char* png : {"baseline.png", "current.png", "difference.png"})
    EXPECT_TRUE(std::filesystem::exists(dir.path() / "ev" / png)) << png;
}

TEST(ChangeDetectionUnit, ImageBudgetDropsTheLargestImagesFirstAndSaysSo) {
  test::TempDir dir("change-budget");
  const std::filesystem::path cls = dir.path() / "llvmpipe-2threads";
  std::filesystem::create_directories(cls);
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::size_t>>{{"big", 600000}, {"mid", 300000},
                                                                                   {"small", 100000}}) {
    std::ofstream(cls / (name + ".exr")) << std::string(bytes, 'x');
    std::ofstream(cls / (name + ".json")) << nlohmann::json{{"scenario", name}, {"image", name + ".exr"}}.dump();
  }
  const ImageBudget b = enforce_image_budget(cls, 0.5);  // 524288 bytes
  EXPECT_EQ(b.dropped, std::vector<std::string>{"big"});
  EXPECT_EQ(b.bytes, 400000u);
  EXPECT_FALSE(std::filesystem::exists(cls / "big.exr"));
  const nlohmann::json doc = test::read_json(cls / "big.json");
  EXPECT_FALSE(doc.contains("image"));
  EXPECT_NE(doc["image_dropped"].get<std::string>().find("budget"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(cls / "mid.exr"));
}

}  // namespace
}  // namespace gi
