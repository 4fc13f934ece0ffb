// The radiance-cascades maths the shaders and the CPU share
// (core/shared/rc/), the canvas scenario (core/rc/canvas.h) and the
// settings the profile gives (core/rc/rc_settings.h).
#include <cmath>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/profile.h"
#include "core/rc/canvas.h"
#include "core/rc/rc_settings.h"
#include "gpu/profile_keys.h"
#include "core/scenario.h"
#include "core/shared/rc/cascades.h"
#include "core/shared/rc/shapes.h"

namespace gi {
namespace {

using namespace gi::shader;

TEST(RcCascades, IntervalsMeetEndToEndAndProbesDoubleInSpacing) {
  for (std::uint32_t rf : {0u, 1u, 2u})
    for (std::uint32_t c = 0; c + 1 < 10; ++c) {
      const RcProbe p = rc_probe_for_cascade(c, rf, 2.0f), q = rc_probe_for_cascade(c + 1, rf, 2.0f);
      EXPECT_FLOAT_EQ(p.start + p.range, q.start) << c;
      EXPECT_FLOAT_EQ(q.range, 4.0f * p.range);
      EXPECT_EQ(q.width, 2u * p.width);
    }
  // The lesson's numbers (seeds/radiance-cascades-lesson.txt:79-81, interval0 2).
  const RcProbe c2 = rc_probe_for_cascade(2, 1, 2.0f);
  EXPECT_EQ(c2.width, 8u);
  EXPECT_FLOAT_EQ(c2.start, 10.0f);
  EXPECT_FLOAT_EQ(c2.range, 32.0f);
}

// Probe `cell` of cascade c is centred at (cell + ½)·w, those of c + 1 at
// (q + ½)·2w: the merge's corners and weights must be the bilinear ones.
TEST(RcCascades, MergeReadsTheTwoNearestCoarserProbesWithBilinearWeights) {
  const float w = 4.0f;
  for (int cell = 0; cell < 16; ++cell) {
    const float centre = (float(cell) + 0.5f) * w;
    const int lo = rc_upper_probe(ivec2(cell), ivec2(-1)).x, hi = rc_upper_probe(ivec2(cell), ivec2(0)).x;
    EXPECT_EQ(hi, lo + 1);
    const float c_lo = (float(lo) + 0.5f) * 2 * w, c_hi = (float(hi) + 0.5f) * 2 * w;
    EXPECT_LE(c_lo, centre);
    EXPECT_GE(c_hi, centre);
    EXPECT_FLOAT_EQ(rc_merge_weight(ivec2(cell)).x, (centre - c_lo) / (c_hi - c_lo)) << cell;
  }
}

TEST(RcCascades, RayDirectionsSplitTheCircleIntoEqualSectors) {
  const std::uint32_t n = 16;
  vec2 sum(0.0f);
  for (std::uint32_t i = 0; i < n; ++i) {
    const vec2 d = rc_ray_direction(i, n);
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
    EXPECT_NEAR(std::atan2(d.y, d.x), std::remainder((i + 0.5) / n * 2 * M_PI, 2 * M_PI), 1e-5);
    sum += d;
  }
  EXPECT_NEAR(glm::length(sum), 0.0f, 1e-5f);
}

// The lesson's mipmap divides a probe's width² rays by width·2: the mean only
// at width 2 (resolution_factor 1); width 4 doubles the output, 8 quadruples it.
TEST(RcCascades, TheLessonsMipmapDivisorIsTheRayCountOnlyAtWidthTwo) {
  for (std::uint32_t rf = 0; rf < 5; ++rf) {
    const std::uint32_t w = 1u << rf;
    const float gain = rc_mipmap_divisor(w, RC_MIPMAP_RAY_COUNT) / rc_mipmap_divisor(w, RC_MIPMAP_PROBE_WIDTH_X2);
    EXPECT_FLOAT_EQ(gain, float(w) / 2.0f) << "resolution_factor " << rf;
  }
}

TEST(RcCascades, CountComesFromTheDiagonalAndTheWidestProbeTilesTheCanvas) {
  EXPECT_EQ(rc_cascades_for_diagonal(std::hypot(128.0f, 128.0f), 2.0f, 16), 5u);   // reaches 2·(4^5 − 1)/3 = 682
  EXPECT_EQ(rc_cascades_for_diagonal(std::hypot(1920.0f, 1080.0f), 2.0f, 16), 6u);  // reaches 2730
  EXPECT_EQ(rc_cascades_for_diagonal(1e9f, 2.0f, 16), 16u);
  EXPECT_EQ(rc_cascades_for_diagonal(0.0f, 2.0f, 16), 1u);
  Profile p = load_profile("radiance-cascades-lesson");
  const RcSettings s = rc_settings(p, 128, 128);
  EXPECT_EQ(s.cascades, 5u);
  EXPECT_FALSE(s.jfa);
  EXPECT_EQ(s.mipmap_mode, RC_MIPMAP_PROBE_WIDTH_X2);
  EXPECT_EQ(s.merge, RC_MERGE_LESSON);
  // 96 = 3·32: cascade 4's 32-px probes tile it, so all five run; 100 is tiled by 4-px probes only.
  EXPECT_EQ(rc_settings(p, 160, 96).cascades, 5u);
  const RcSettings odd = rc_settings(p, 100, 100);
  EXPECT_EQ(odd.cascades_for_diagonal, 4u);
  EXPECT_EQ(odd.cascades, 2u);
  EXPECT_EQ(odd.interval_boundaries(), std::vector<float>{2.0f});
}

// The analytic distances against a brute-force distance to each boundary.
TEST(RcShapes, SignedDistancesAreExact) {
  RcShape e{};
  e.geometry = vec4(20, 30, 12, 5);
  e.info = uvec4(RC_SHAPE_ELLIPSE, 0, 0, 0);
  RcShape r{};
  r.geometry = vec4(-3, 2, 7, 9);
  r.info = uvec4(RC_SHAPE_RECT, 0, 0, 0);
  RcShape s{};
  s.geometry = vec4(0, 0, 10, 4);
  s.radiance = vec4(0, 0, 0, 1.5f);
  s.info = uvec4(RC_SHAPE_SEGMENT, 0, 0, 0);
  for (int i = 0; i < 400; ++i) {
    const vec2 p(std::fmod(i * 7.31f, 50.0f) - 10.0f, std::fmod(i * 3.17f, 50.0f) - 5.0f);
    float d_e = 1e9f;
    for (int k = 0; k < 20000; ++k) {
      const float t = float(k) / 20000 * TWO_PI;
      d_e = std::min(d_e, glm::length(p - vec2(20 + 12 * std::cos(t), 30 + 5 * std::sin(t))));
    }
    const float fe = rc_sdf(p, e);
    if (fe > 0) {
      EXPECT_NEAR(fe, d_e, 2e-3f) << p.x << "," << p.y;
    }
    const float dx = std::max({-3 - p.x, p.x - 7, 0.0f}), dy = std::max({2 - p.y, p.y - 9, 0.0f});
    if (dx > 0 || dy > 0) {
      EXPECT_NEAR(rc_sdf(p, r), std::hypot(dx, dy), 1e-4f);
    }
    const float h = std::clamp(glm::dot(p, vec2(10, 4)) / 116.0f, 0.0f, 1.0f);
    EXPECT_NEAR(rc_sdf(p, s), glm::length(p - h * vec2(10, 4)) - 1.5f, 1e-4f);
  }
}

Scenario canvas_scenario(const nlohmann::json& events) {
  nlohmann::json doc = {
      {"name", "canvas"}, {"pipeline", "radiance_cascades"}, {"resolution", {32, 32}}, {"frames", 10},
      {"scene",
       {{"shapes",
         {{{"name", "lamp"}, {"type", "ellipse"}, {"center", {8, 8}}, {"radii", {2, 2}}, {"emission", {1, 1, 1}}},
          {{"name", "fence"}, {"type", "polyline"}, {"points", {{16, 0}, {16, 10}, {20, 20}}}, {"width", 2}}}}}},
      {"events", events}};
  return parse_scenario(doc, "canvas.json");
}

TEST(RcCanvas, EventsGiveTheCanvasAtAFrame) {
  const Scenario s = canvas_scenario({{{"type", "transform"}, {"frames", {2, 6}}, {"instance", "fence"}, {"translation", {8, 0, 0}}},
                                      {{"type", "light_off"}, {"frame", 3}, {"light", "lamp"}},
                                      {{"type", "light_on"}, {"frame", 5}, {"light", "lamp"}},
                                      {{"type", "light_intensity"}, {"frame", 5}, {"light", "lamp"}, {"scale", 3}}});
  EXPECT_EQ(s.profile, "radiance-cascades-lesson");
  const Canvas& c0 = *s.canvas;
  EXPECT_EQ(c0.gpu_shapes().size(), 3u);  // the polyline's two edges
  EXPECT_EQ(canvas_at_frame(c0, s, 4).find("fence")->offset.x, 4.0f);
  EXPECT_EQ(canvas_at_frame(c0, s, 9).find("fence")->offset.x, 8.0f);
  EXPECT_EQ(canvas_at_frame(c0, s, 4).find("lamp")->radiance(), glm::vec3(0.0f));
  EXPECT_EQ(canvas_at_frame(c0, s, 5).find("lamp")->radiance(), glm::vec3(3.0f));
  EXPECT_EQ(canvas_at_frame(c0, s, 0).hash(), c0.hash());
  EXPECT_NE(canvas_at_frame(c0, s, 3).hash(), c0.hash());
  EXPECT_EQ(canvas_at_frame(c0, s, 3).gpu_shapes()[1].geometry, vec4(18, 0, 18, 10));
}

TEST(RcCanvas, BadShapesAndEventsNameTheirPath) {
  auto path_of = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return e.json_path();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(path_of([] { canvas_scenario({{{"type", "transform"}, {"frame", 1}, {"instance", "fence"}, {"translation", {1, 0, 2}}}}); }),
            "/events/0/translation/2");
  EXPECT_EQ(path_of([] { canvas_scenario({{{"type", "light_color"}, {"frame", 1}, {"light", "fence"}, {"color", {1, 0, 0}}}}); }),
            "/events/0/light");
  EXPECT_EQ(path_of([] { canvas_scenario({{{"type", "transform"}, {"frame", 1}, {"instance", "fence"}, {"scale", 2}}}); }),
            "/events/0");
  nlohmann::json doc = {{"name", "c"}, {"pipeline", "radiance_cascades"}, {"resolution", {8, 8}}, {"frames", 1},
                        {"scene", {{"shapes", {{{"name", "a"}, {"type", "rect"}, {"min", {4, 4}}, {"max", {2, 6}}}}}}}};
  EXPECT_EQ(path_of([&] { parse_scenario(doc, "c.json"); }), "/scene/shapes/0/max");
  doc["scene"]["shapes"][0] = {{"name", "a"}, {"type", "line"}, {"from", {0, 0}}, {"width", 1}};
  EXPECT_EQ(path_of([&] { parse_scenario(doc, "c.json"); }), "/scene/shapes/0/to");
  doc["scene"] = {{"generator", "cornell_box"}};
  EXPECT_EQ(path_of([&] { parse_scenario(doc, "c.json"); }), "/scene/generator");
  doc["pipeline"] = "solari";
  doc["profile"] = "radiance-cascades-lesson";
  EXPECT_EQ(path_of([&] { parse_scenario(doc, "c.json"); }), "/profile");
}

}  // namespace
}  // namespace gi
