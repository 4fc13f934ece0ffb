// Irradiance at surface points by the Embree path tracer: the reference the
// world cache's bias is measured against. E(p, n) = ∫ L_i cos θ dω,
// estimated with cosine-distributed directions, each radiance L_i from the
// shared path integrator (core/shared/path_integrator.h) exactly as the
// reference image's camera rays get theirs. Deterministic per seed at any
// thread count (one random stream per point).
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene_flatten.h"

namespace gi {

struct IrradiancePoint {
  glm::vec3 position;
  glm::vec3 normal;  // unit, on the side whose irradiance is wanted
};

struct IrradianceOptions {
  std::uint32_t samples = 1024;  // directions per point
  std::uint32_t seed = 1;
  std::uint32_t max_bounces = 32;
  unsigned threads = 0;          // 0 = all cores; never changes the result
};

// One estimate per point (rgb irradiance).
std::vector<glm::vec3> embree_irradiance(const FlatGeometry& geometry, const FlatInstances& instances,
                                         const std::vector<std::uint8_t>& visible,
                                         const std::vector<IrradiancePoint>& points, const IrradianceOptions& options);

}  // namespace gi
