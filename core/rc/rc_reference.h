// The radiance-cascades pipeline's reference (issue 18): a 2D path tracer
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

// The nearest t > 0 at which the ray origin + t·dir (dir unit length, origin
// outside the shape) enters the shape; infinity when it does not.
float rc_intersect(const shader::RcShape& shape, glm::vec2 origin, glm::vec2 dir);
// The radiance one ray carries: that of the first shape it enters.
glm::vec3 rc_trace(const std::vector<shader::RcShape>& shapes, glm::vec2 origin, glm::vec2 dir);

}  // namespace gi
