// The radiance-cascades pipeline on the device (gpu/rc/, replay/rc_run.h):
// jump flooding against the analytic distance field, bit-identical frames
// across runs and lavapipe thread counts, events that change exactly the
// frames they should, and captures that hold every intermediate.
#include <algorithm>
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "core/exr_io.h"
#include "core/profile.h"
#include "core/rc/rc_settings.h"
#include "gpu/profile_keys.h"
#include "gpu/device.h"
#include "gpu/rc/rc_pipeline.h"
#include "gpu/shader_compiler.h"
#include "tests/test_support.h"

namespace gi {
namespace {

Canvas distance_canvas() {
  Canvas c;
  c.width = 128;
  c.height = 96;
  auto add = [&](std::string name, std::string type, std::vector<glm::vec2> pts, float half_width = 0) {
    CanvasShape s;
    s.name = std::move(name);
    s.type = std::move(type);
    s.points = std::move(pts);
    s.half_width = half_width;
    c.shapes.push_back(s);
  };
  add("box", "rect", {{10.2f, 12.7f}, {30.5f, 40.1f}});
  add("disc", "ellipse", {{70.3f, 30.6f}, {9.2f, 9.2f}});
  add("oval", "ellipse", {{100.0f, 70.0f}, {18.0f, 6.5f}});
  add("stroke", "line", {{20.0f, 80.0f}, {60.0f, 60.0f}}, 1.5f);
  add("zigzag", "polyline", {{80.0f, 5.0f}, {90.0f, 20.0f}, {110.0f, 10.0f}}, 2.0f);
  return c;
}

std::vector<float> distance_field(const std::string& mode) {
  gpu::Device device(std::nullopt, test::test_backend());
  gpu::ShaderCompiler compiler;
  Profile p = load_profile("radiance-cascades-lesson");
  apply_set(p, "rc.distance_field=" + mode);
  const Canvas canvas = distance_canvas();
  gpu::RcPipeline pipeline(device, compiler, rc_settings(p, canvas.width, canvas.height));
  pipeline.set_canvas(canvas);
  device.submit_and_wait([&](VkCommandBuffer cmd) { pipeline.record(cmd); });
  return pipeline.distance();
}

// JFA keeps the nearest pixel centre inside a shape and takes half a pixel
// off the distance to it; the analytic field is the exact distance to the
// boundary from each pixel centre. Their largest difference over the canvas,
// in pixels, is the JFA's error: half a pixel from the centre-to-boundary
// guess, and more where a round's nine samples miss the nearest seed (jump
// flooding's known approximation; 1.2 px here).
TEST(RcPipeline, JumpFloodingAgainstTheAnalyticDistanceField) {
  const std::vector<float> analytic = distance_field("analytic"), jfa = distance_field("jfa");
  ASSERT_EQ(analytic.size(), jfa.size());
  double worst = 0, sum = 0;
  std::size_t inside = 0, at = 0;
  for (std::size_t i = 0; i < analytic.size(); ++i) {
    if (analytic[i] == 0.0f) {
      ++inside;
      EXPECT_EQ(jfa[i], 0.0f) << i;  // the same pixels are inside
    }
    const double e = std::abs(double(jfa[i]) - double(analytic[i]));
    sum += e;
    if (e > worst) worst = e, at = i;
  }
  std::printf("JFA against analytic over %zu pixels (%zu inside): max error %.3f px at (%zu, %zu), mean %.4f px\n",
              analytic.size(), inside, worst, at % 128, at / 128, sum / double(analytic.size()));
  EXPECT_GT(inside, 1000u);
  EXPECT_LE(worst, 1.5);
  EXPECT_LE(sum / double(analytic.size()), 0.25);
}

nlohmann::json run(const std::filesystem::path& out, const std::string& env, const std::string& extra = "") {
  const std::string scenario = (test::source_dir() / "scenarios/rc_lamp_and_wall.json").string();
  const auto r = test::run_giharness("run " + scenario + " --out " + out.string() + " " + extra, env);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return test::read_json(out / "summary.json");
}

TEST(RcPipeline, BitIdenticalAcrossRunsAndLavapipeThreadCounts) {
  test::TempDir dir("rc_determinism");
  const nlohmann::json a = run(dir.path() / "a", "LP_NUM_THREADS=1");
  const nlohmann::json b = run(dir.path() / "b", "LP_NUM_THREADS=2");
  const nlohmann::json c = run(dir.path() / "c", "LP_NUM_THREADS=2");
  ASSERT_EQ(a["hashes"]["frame_images"].size(), 10u);
  EXPECT_EQ(a["hashes"], b["hashes"]);
  EXPECT_EQ(b["hashes"], c["hashes"]);
  EXPECT_EQ(a["final_image_hash"], b["final_image_hash"]);
  EXPECT_EQ(a["checks"][0]["figures"], b["checks"][0]["figures"]);
  EXPECT_EQ(a["device"]["lp_num_threads"], "1");
}

// rc_lamp_and_wall: the lamp moves over frames 0-6, the spot goes off at 4 and on at 8.
TEST(RcPipeline, EventsChangeExactlyTheFramesTheyShould) {
  test::TempDir dir("rc_events");
  const nlohmann::json s = run(dir.path(), "");
  const nlohmann::json& h = s["hashes"]["frame_images"];
  for (int f = 1; f <= 6; ++f) EXPECT_NE(h[f], h[f - 1]) << f;
  EXPECT_EQ(h[7], h[6]);  // nothing changes between 6 and 8
  EXPECT_NE(h[8], h[7]);  // the spot comes back
  EXPECT_EQ(h[9], h[8]);
  // A frame is a pure function of the scenario and its index: a shorter run's frames are the long run's.
  const nlohmann::json short_run = run(dir.path() / "short", "", "--frames 5");
  for (int f = 0; f < 5; ++f) EXPECT_EQ(short_run["hashes"]["frame_images"][f], h[f]) << f;
}

TEST(RcPipeline, CapturesHoldTheDistanceFieldEveryCascadeAndTheMipmap) {
  test::TempDir dir("rc_capture");
  const nlohmann::json s = run(dir.path(), "");
  ASSERT_EQ(s["captures"].size(), 1u);
  const auto layers = read_exr(dir.path() / s["captures"][0].get<std::string>());
  for (const char* name : {"", "scene", "distance", "cascade_0", "cascade_1", "cascade_2", "cascade_3", "cascade_4"})
    EXPECT_TRUE(layers.count(name)) << name;
  EXPECT_FALSE(layers.count("cascade_5"));
  const Image& distance = layers.at("distance");
  const Image& scene = layers.at("scene");
  for (std::size_t i = 0; i < distance.size(); ++i)
    if (scene.pixels[i] != glm::vec3(0.0f)) {
      EXPECT_EQ(distance.pixels[i].x, 0.0f);
    }
  // The output layer is the run's last frame (frame 9 is captured and last).
  const auto final_image = read_exr(dir.path() / "final_image.exr").at("");
  double diff = 0;
  for (std::size_t i = 0; i < distance.size(); ++i)
    diff = std::max(diff, double(glm::length(final_image.pixels[i] - layers.at("").pixels[i])));
  EXPECT_LT(diff, 2e-3);  // the final image is stored as half floats
  const auto mip = read_exr(dir.path() / "captures/frame_00009/mipmap.exr").at("");
  EXPECT_EQ(mip.width, 64u);
  EXPECT_EQ(mip.height, 64u);
}

// A capture replays bit for bit: the replay renders the captured frame again
// and the frames after it, and --verify holds each to the capturing run's hash.
TEST(RcPipeline, ReplayFromACaptureIsBitIdenticalAndVerifyNoticesADifference) {
  test::TempDir dir("rc_replay");
  run(dir.path() / "run", "", "--capture 5");
  const std::filesystem::path capture = dir.path() / "run/captures/frame_00005";
  const auto ok = test::run_giharness("replay " + capture.string() + " --verify --out " + (dir.path() / "replay").string());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  const nlohmann::json v = test::read_json(dir.path() / "replay/verify.json");
  EXPECT_EQ(v["verdict"], "identical");
  EXPECT_EQ(v["compared"], 5);
  EXPECT_EQ(test::read_json(dir.path() / "replay/summary.json")["resumed_from"]["same_bits"], true);
  // A capturing run whose frame 7 had other bits: the replay names it.
  nlohmann::json hashes = test::read_json(capture / "run_hashes.json");
  hashes["frame_images"][7] = "0000000000000000";
  std::ofstream(capture / "run_hashes.json") << hashes.dump();
  const auto bad = test::run_giharness("replay " + capture.string() + " --verify --out " + (dir.path() / "again").string());
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_EQ(test::read_json(dir.path() / "again/verify.json")["message"], "frame 7's image differs from the capturing run's");
}

}  // namespace
}  // namespace gi
