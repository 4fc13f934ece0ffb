// Deterministic ray sets for comparing and timing the tracing backends
// (the backend cross-check test, `giharness bench --rays`): camera rays,
// diffuse (cosine) rays leaving visible surfaces, and rays between random
// points of the scene's bounds, some with a finite tmax.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/scene_flatten.h"

namespace gi::bvh {

struct TraceRay {
  glm::vec3 origin;
  glm::vec3 direction;  // unit
  float tmax;
};

enum class RayKind { camera, diffuse, box, mixed };

struct RaySetOptions {
  std::uint32_t count = 100000;
  std::uint32_t seed = 1;
  RayKind kind = RayKind::mixed;  // mixed: a third of each, every tenth with a finite tmax
  // The camera for camera rays (pixel positions jittered inside the image).
  GpuCamera camera{};
};

// visible[i]: instance i is drawn (a missing entry = visible). The same
// inputs give the same rays on every machine (a fixed-width PCG, no std distributions).
std::vector<TraceRay> make_ray_set(const FlatGeometry& geometry, const FlatInstances& instances,
                                   const std::vector<bool>& visible, const RaySetOptions& options);

}  // namespace gi::bvh
