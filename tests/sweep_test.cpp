// `giharness sweep`: the product of --vary axes over a scenario, and the
// error-against-time table with the Embree path tracer at equal time.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/errors.h"
#include "app/sweep_plan.h"
#include "tests/test_support.h"

namespace gi {
namespace {

TEST(SweepPlan, CartesianProductOverScenarioPointerAndProfileKeys) {
  const nlohmann::json base = {{"name", "x"}, {"resolution", {8, 8}}, {"scene", {{"params", {{"light_scale", 1.0}}}}}};
  const std::vector<SweepAxis> axes = {parse_sweep_axis("samples_per_frame=1,4"),
                                       parse_sweep_axis("resolution=16x9,[32,18]"),
                                       parse_sweep_axis("/scene/params/light_scale=0.5"),
                                       parse_sweep_axis("restir_di.initial_samples=8")};
  const std::vector<SweepPoint> points = sweep_points(base, axes);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(points[0].document["samples_per_frame"], 1);
  EXPECT_EQ(points[1].document["resolution"], nlohmann::json({32, 18}));
  EXPECT_EQ(points[2].document["samples_per_frame"], 4);
  EXPECT_EQ(points[2].document["resolution"], nlohmann::json({16, 9}));
  EXPECT_EQ(points[3].document["scene"]["params"]["light_scale"], 0.5);
  EXPECT_EQ(points[3].document["overrides"]["restir_di.initial_samples"], 8);
  EXPECT_EQ(points[3].label(), "samples_per_frame=4 resolution=[32,18] /scene/params/light_scale=0.5 restir_di.initial_samples=8");
  EXPECT_EQ(base["resolution"], nlohmann::json({8, 8}));  // the base is not changed
}

TEST(SweepPlan, MalformedAxesAreBadInputNamingVary) {
  for (const char* bad : {"samples_per_frame", "=1,2", "samples_per_frame=", "samples_per_frame=1,,2"}) {
    try {
      parse_sweep_axis(bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "--vary") << bad;
    }
  }
  EXPECT_THROW(sweep_points(nlohmann::json::object(), {parse_sweep_axis("/no/such=1")}), InputError);
}

TEST(Sweep, ErrorAgainstTimeWithEmbreeAtEqualTime) {
  test::TempDir dir("sweep");
  const std::filesystem::path scenario = test::source_dir() / "tests/data/suites/tiny/tiny_cornell.json";
  const test::CommandResult r = test::run_giharness("sweep " + scenario.string() +
                                                    " --vary samples_per_frame=1,16 --reference-spp 256 --out " +
                                                    dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json sweep = test::read_json(dir.path() / "sweep.json");
  ASSERT_EQ(sweep["rows"].size(), 4u) << sweep.dump(2);
  std::vector<double> gpu_error, gpu_ms;
  for (const nlohmann::json& row : sweep["rows"]) {
    ASSERT_TRUE(row["relmse"].is_number()) << row.dump();  // reference mode: no GPU path tracer peer (the point is one)
    ASSERT_TRUE(row["ms_per_frame"].is_number()) << row.dump();
    EXPECT_GT(row["relmse"].get<double>(), 0.0);
    if (row["kind"] == "gpu") {
      gpu_error.push_back(row["relmse"]);
      gpu_ms.push_back(row["ms_per_frame"]);
    } else {
      EXPECT_EQ(row["kind"], "embree_equal_time");
      EXPECT_GE(row["spp"].get<unsigned>(), 1u);
    }
  }
  ASSERT_EQ(gpu_error.size(), 2u);
  // 16x the samples: the error falls (relMSE ~ 1/N would give 16x; noise of
  // a 32x32 image and the reference's own noise leave less). Times are
  // figures, not assertions (a loaded machine may order them either way).
  EXPECT_LT(gpu_error[1], gpu_error[0] / 3.0);
  for (double ms : gpu_ms) EXPECT_GT(ms, 0.0);
  std::ifstream in(dir.path() / "report.html");
  const std::string html{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_NE(html.find("Embree (equal time)"), std::string::npos);
  EXPECT_NE(html.find("data:image/svg+xml;base64,"), std::string::npos);
}

// A GI scenario's realtime image is DI + GI + specular: the sweep must judge
// it (and run its Embree peer) with the full path tracer, not DI alone.
TEST(Sweep, GiScenarioIsComparedWithTheFullGiReference) {
  test::TempDir dir("sweep_gi");
  const std::filesystem::path scenario = test::source_dir() / "scenarios/gi_cornell_box.json";
  const test::CommandResult r = test::run_giharness("sweep " + scenario.string() +
                                                    " --vary resolution=32x18 --reference-spp 64 --out " +
                                                    dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json sweep = test::read_json(dir.path() / "sweep.json");
  ASSERT_EQ(sweep["reference"].size(), 1u) << sweep.dump(2);
  EXPECT_EQ(sweep["reference"][0]["direct_only"], false) << sweep["reference"].dump(2);
  for (const nlohmann::json& row : sweep["rows"]) EXPECT_TRUE(row["relmse"].is_number()) << row.dump();
  // A realtime point has the GPU path tracer beside it, on fresh sample indices.
  std::size_t peers = 0;
  for (const nlohmann::json& row : sweep["rows"])
    if (row["kind"] == "gpu_path_tracer_equal_time") {
      ++peers;
      EXPECT_GE(row["sample_indices"][0].get<unsigned>(), 64u) << row.dump();
      EXPECT_TRUE(row["equal_error_time_ratio_frame"].is_number()) << row.dump();
    }
  EXPECT_EQ(peers, 1u) << sweep.dump(2);
}

}  // namespace
}  // namespace gi
