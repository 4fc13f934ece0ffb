// The radiance-cascades pipeline's reference, the 2D path tracer
// (core/rc/rc_reference.h): exact against an analytic case, its
// intersections on the shapes' boundaries, bit-identical at any thread count.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "core/rc/rc_reference.h"
#include "core/shared/rc/shapes.h"

namespace gi {
namespace {

Canvas lamp_canvas(float radius) {
  Canvas c;
  c.width = c.height = 64;
  CanvasShape lamp;
  lamp.name = "lamp";
  lamp.type = "ellipse";
  lamp.points = {glm::vec2(32, 32), glm::vec2(radius, radius)};
  lamp.emission = glm::vec3(2.0f, 1.0f, 0.5f);
  lamp.emissive = true;
  c.shapes.push_back(lamp);
  return c;
}

// A disc of radius r seen from distance d fills the angle 2·asin(r/d): the
// mean radiance over directions is L·asin(r/d)/π. With N stratified rays
// only the two strata the disc's edges fall in are partly covered, so the
// estimate is within 2L/N of it, at every pixel.
TEST(RcReference, ADiscFallsOffAsTheAngleItSubtends) {
  const std::uint32_t rays = 1024;
  for (float r : {1.5f, 6.0f}) {
    const Canvas c = lamp_canvas(r);
    const RcReference ref = rc_reference(c, {.rays = rays, .seed = 3});
    double worst = 0;
    for (std::uint32_t y = 0; y < 64; ++y)
      for (std::uint32_t x = 0; x < 64; ++x) {
        const std::size_t i = y * 64 + x;
        const float d = glm::length(glm::vec2(x, y) + 0.5f - glm::vec2(32));
        ASSERT_EQ(ref.free[i] == 1, d > r) << x << "," << y;
        if (!ref.free[i]) continue;
        const double exact = 2.0 * std::asin(r / d) / M_PI;  // L = 2 in red
        worst = std::max(worst, std::abs(double(ref.mean.pixels[i].x) - exact));
      }
    EXPECT_LE(worst, 2.0 * 2.0 / rays) << "radius " << r;
    std::printf("disc of radius %.1f: largest error %.2e (bound %.2e)\n", r, worst, 4.0 / rays);
  }
}

TEST(RcReference, IntersectionsLieOnTheShapesBoundaries) {
  std::vector<shader::RcShape> shapes(3);
  shapes[0].geometry = glm::vec4(10, 10, 20, 14);
  shapes[0].info.x = shader::RC_SHAPE_RECT;
  shapes[1].geometry = glm::vec4(40, 20, 9, 4);
  shapes[1].info.x = shader::RC_SHAPE_ELLIPSE;
  shapes[2].geometry = glm::vec4(10, 40, 30, 50);
  shapes[2].radiance.w = 2.5f;
  shapes[2].info.x = shader::RC_SHAPE_SEGMENT;
  int hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const glm::vec2 o(float(k % 53), float((k * 7) % 61));
    const double a = k * 0.618 * 2 * M_PI;
    const glm::vec2 d(float(std::cos(a)), float(std::sin(a)));
    for (const shader::RcShape& s : shapes) {
      if (shader::rc_sdf(o, s) <= 0) continue;
      const float t = rc_intersect(s, o, d);
      if (!std::isfinite(t)) {
        // A miss: nothing along the ray is inside.
        for (float u = 0; u < 100; u += 0.05f) ASSERT_GT(shader::rc_sdf(o + u * d, s), -1e-3f);
        continue;
      }
      ++hits;
      EXPECT_NEAR(shader::rc_sdf(o + t * d, s), 0.0f, 2e-3f);
      // and nothing before it is.
      for (float u = 0; u < t - 0.01f; u += 0.05f) ASSERT_GT(shader::rc_sdf(o + u * d, s), -1e-3f);
    }
  }
  EXPECT_GT(hits, 500);
}

TEST(RcReference, BitIdenticalAtAnyThreadCount) {
  Canvas c = lamp_canvas(4.0f);
  CanvasShape wall;
  wall.name = "wall";
  wall.type = "line";
  wall.points = {glm::vec2(40, 10), glm::vec2(44, 50)};
  wall.half_width = 1.0f;
  c.shapes.push_back(wall);
  const RcReference many = rc_reference(c, {.rays = 64, .seed = 9});
  RcReference one;
  tbb::task_arena arena(1);
  arena.execute([&] { one = rc_reference(c, {.rays = 64, .seed = 9}); });
  ASSERT_EQ(many.mean.size(), one.mean.size());
  EXPECT_EQ(std::memcmp(many.mean.pixels.data(), one.mean.pixels.data(), many.mean.size() * sizeof(glm::vec3)), 0);
  EXPECT_EQ(std::memcmp(many.half_a.pixels.data(), one.half_a.pixels.data(), many.mean.size() * sizeof(glm::vec3)), 0);
  // The halves are independent estimates: not the same image.
  EXPECT_NE(std::memcmp(many.half_a.pixels.data(), many.half_b.pixels.data(), many.mean.size() * sizeof(glm::vec3)), 0);
}

}  // namespace
}  // namespace gi
