// The radiance-cascades pipeline's reference: a 2D path tracer
// on the CPU that computes what the lesson's output means, the radiance at
// a pixel centre averaged over all directions (fluence / 2π), from rays
// intersected exactly with the analytic shapes — no distance field, no
// probes, no march. Shapes are opaque: a ray ends at the first it enters
// and carries that shape's emitted radiance (occluders: none).
//
// Directions are stratified: ray j of N in [j, j + 1)·2π/N with a jitter
// hashed from (seed, pixel, j), so the image is exact up to noise and
// bit-identical at any thread count. Even and odd strata make two
// independent half estimates (the noise the checks' tolerances allow for).
// Inside a shape the reference is the shape's radiance and the pixel is not
// `free`: the checks judge free pixels only.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "core/rc/canvas.h"

namespace gi {

struct RcReferenceOptions {
  std::uint32_t rays = 1024;  // per pixel (even)
  std::uint32_t seed = 1;
};

struct RcReference {
  Image mean, half_a, half_b;
  std::vector<std::uint8_t> free;  // 1 where the pixel centre is outside every shape
  std::uint32_t rays = 0;
  double seconds = 0.0;
  std::size_t free_count() const;
};

RcReference rc_reference(const Canvas& canvas, const RcReferenceOptions& options);

// An image against the reference over the free pixels of [x0, x1) × [y0, y1)
// (luminance, summed in double in row order): what the rc checks and the
// sweep measure.
struct RcComparison {
  std::size_t pixels = 0;
  double output = 0, reference = 0;  // ΣY, ΣY_ref
  double abs_error = 0, sq_error = 0, reference_sq = 0;  // Σ|Y − Y_ref|, Σ(Y − Y_ref)², ΣY_ref²
  double noise_abs = 0, noise_var = 0;  // Σ½|Y_a − Y_b|, Σ(Y_a − Y_b)²/4: the reference's own noise
  double relative_l1() const { return reference > 0 ? abs_error / reference : 0.0; }
  double relmse() const { return reference_sq > 0 ? sq_error / reference_sq : 0.0; }
  double energy_ratio() const { return reference > 0 ? output / reference : 0.0; }
};
double rc_luminance(const glm::vec3& c);  // Rec. 709, in double
RcComparison rc_compare(const Image& image, const RcReference& reference, std::uint32_t x0, std::uint32_t y0,
                        std::uint32_t x1, std::uint32_t y1);
inline RcComparison rc_compare(const Image& image, const RcReference& reference) {
  return rc_compare(image, reference, 0, 0, image.width, image.height);
}

// The nearest t > 0 at which the ray origin + t·dir (dir unit length, origin
// outside the shape) enters the shape; infinity when it does not.
float rc_intersect(const shader::RcShape& shape, glm::vec2 origin, glm::vec2 dir);
// The radiance one ray carries: that of the first shape it enters.
glm::vec3 rc_trace(const std::vector<shader::RcShape>& shapes, glm::vec2 origin, glm::vec2 dir);

}  // namespace gi
