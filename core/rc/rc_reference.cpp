#include "core/rc/rc_reference.h"

#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "core/shared/rng.h"

namespace gi {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr std::uint32_t kDomain = 0x27D4EB2Fu;  // this reference's own stream

float first_positive(float t0, float t1) { return t0 > 0.0f ? t0 : (t1 > 0.0f ? t1 : kInf); }

float hit_rect(glm::vec4 g, glm::vec2 o, glm::vec2 d) {
  float t_near = -kInf, t_far = kInf;
  for (int a = 0; a < 2; ++a) {
    const float lo = a == 0 ? g.x : g.y, hi = a == 0 ? g.z : g.w;
    if (d[a] == 0.0f) {
      if (o[a] < lo || o[a] > hi) return kInf;
      continue;
    }
    float t0 = (lo - o[a]) / d[a], t1 = (hi - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    t_near = std::max(t_near, t0);
    t_far = std::min(t_far, t1);
  }
  return t_near <= t_far && t_near > 0.0f ? t_near : kInf;
}

// A circle (or, scaled, an ellipse): the smaller root of |o + t d − c|² = 1.
float hit_unit_circle(glm::vec2 o, glm::vec2 d) {
  const float a = glm::dot(d, d), b = glm::dot(o, d), c = glm::dot(o, o) - 1.0f;
  const float disc = b * b - a * c;
  if (disc < 0.0f) return kInf;
  const float s = std::sqrt(disc);
  return first_positive((-b - s) / a, (-b + s) / a);
}

float hit_ellipse(glm::vec4 g, glm::vec2 o, glm::vec2 d) {
  const glm::vec2 r(g.z, g.w);
  return hit_unit_circle((o - glm::vec2(g.x, g.y)) / r, d / r);
}

// A stroked segment (a capsule): its boundary is two sides parallel to the
// segment and two half circles; from outside, the first crossing of the sides
// (within the segment's span) or of the end circles is where the ray enters.
float hit_capsule(glm::vec4 g, float hw, glm::vec2 o, glm::vec2 d) {
  const glm::vec2 a(g.x, g.y), b(g.z, g.w);
  float t = std::min(hit_unit_circle((o - a) / hw, d / hw), hit_unit_circle((o - b) / hw, d / hw));
  const glm::vec2 ab = b - a;
  const float len = glm::length(ab);
  if (len == 0.0f) return t;
  const glm::vec2 u = ab / len, n(-u.y, u.x);
  const float dn = glm::dot(d, n);
  if (dn != 0.0f)
    for (float side : {-hw, hw}) {
      const float ts = (side - glm::dot(o - a, n)) / dn;
      if (ts <= 0.0f || ts >= t) continue;
      const float h = glm::dot(o + ts * d - a, u);
      if (h >= 0.0f && h <= len) t = ts;
    }
  return t;
}

}  // namespace

double rc_luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

RcComparison rc_compare(const Image& image, const RcReference& ref, std::uint32_t x0, std::uint32_t y0,
                        std::uint32_t x1, std::uint32_t y1) {
  RcComparison c;
  for (std::uint32_t y = y0; y < y1; ++y)
    for (std::uint32_t x = x0; x < x1; ++x) {
      const std::size_t i = std::size_t(y) * image.width + x;
      if (!ref.free[i]) continue;
      const double o = rc_luminance(image.pixels[i]), r = rc_luminance(ref.mean.pixels[i]);
      const double d = rc_luminance(ref.half_a.pixels[i]) - rc_luminance(ref.half_b.pixels[i]);
      ++c.pixels;
      c.output += o, c.reference += r;
      c.abs_error += std::abs(o - r), c.sq_error += (o - r) * (o - r), c.reference_sq += r * r;
      c.noise_abs += 0.5 * std::abs(d), c.noise_var += d * d / 4.0;
    }
  return c;
}

std::size_t RcReference::free_count() const {
  std::size_t n = 0;
  for (std::uint8_t f : free) n += f;
  return n;
}

float rc_intersect(const shader::RcShape& s, glm::vec2 o, glm::vec2 d) {
  if (s.info.x == shader::RC_SHAPE_RECT) return hit_rect(s.geometry, o, d);
  if (s.info.x == shader::RC_SHAPE_ELLIPSE) return hit_ellipse(s.geometry, o, d);
  return hit_capsule(s.geometry, s.radiance.w, o, d);
}

glm::vec3 rc_trace(const std::vector<shader::RcShape>& shapes, glm::vec2 o, glm::vec2 d) {
  float best = kInf;
  glm::vec3 L(0.0f);
  for (const shader::RcShape& s : shapes) {
    const float t = rc_intersect(s, o, d);
    if (t < best) {
      best = t;
      L = glm::vec3(s.radiance);
    }
  }
  return L;
}

RcReference rc_reference(const Canvas& canvas, const RcReferenceOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const std::uint32_t W = canvas.width, H = canvas.height;
  const std::uint32_t N = std::max(2u, options.rays & ~1u);
  const std::vector<shader::RcShape> shapes = canvas.gpu_shapes();
  RcReference ref;
  ref.mean = ref.half_a = ref.half_b = Image(W, H);
  ref.free.assign(std::size_t(W) * H, 0);
  ref.rays = N;
  tbb::parallel_for(std::uint32_t(0), H, [&](std::uint32_t y) {
    for (std::uint32_t x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * W + x;
      const glm::vec2 p = glm::vec2(x, y) + 0.5f;
      // Inside a shape (the raster's rule, core/shared/rc/shapes.h): its radiance.
      const shader::RcShape* inside = nullptr;
      for (const shader::RcShape& s : shapes)
        if (shader::rc_sdf(p, s) <= 0.0f) inside = &s;
      if (inside) {
        ref.mean.pixels[i] = ref.half_a.pixels[i] = ref.half_b.pixels[i] = glm::vec3(inside->radiance);
        continue;
      }
      ref.free[i] = 1;
      glm::dvec3 sum[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
      for (std::uint32_t j = 0; j < N; ++j) {
        std::uint32_t state = shader::rng_seed(options.seed, kDomain, std::uint32_t(i), j);
        const float u = shader::rng_next_float(state);
        const double angle = (double(j) + double(u)) / double(N) * 2.0 * M_PI;
        const glm::vec2 d(float(std::cos(angle)), float(std::sin(angle)));
        sum[j & 1u] += glm::dvec3(rc_trace(shapes, p, d));
      }
      const double half = double(N / 2);
      ref.half_a.pixels[i] = glm::vec3(sum[0] / half);
      ref.half_b.pixels[i] = glm::vec3(sum[1] / half);
      ref.mean.pixels[i] = glm::vec3((sum[0] + sum[1]) / double(N));
    }
  });
  ref.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return ref;
}

}  // namespace gi
