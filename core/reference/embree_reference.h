// The Embree reference path tracer (docs/design.md §5): the shared path_trace()
// (core/shared/path_integrator.h) with rays traced by Embree 3 instead of
// GPU ray queries. Pixel-centre primary rays, deterministic per seed at any
// thread count, two independent half-sample images for its own noise.
#pragma once
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/scene.h"
#include "core/scene_flatten.h"

namespace gi {

struct ReferenceOptions {
  std::uint32_t width = 0, height = 0;
  std::uint32_t spp = 0;
  std::uint32_t seed = 1;
  std::uint32_t max_bounces = 32;
  unsigned threads = 0;            // 0 = all cores; never changes the image
  std::uint32_t first_sample = 0;  // sample indices first_sample .. first_sample + spp − 1
  bool direct_only = false;        // "DI" only (core/shared/direct_integrator.h), for the realtime DI check
  glm::vec3 background{0.0f};      // added where the camera ray misses (Scene::background)
};

struct ReferenceResult {
  Image mean;    // all finite samples
  Image half_a;  // even sample indices
  Image half_b;  // odd sample indices
  std::uint64_t nonfinite_samples = 0;  // samples with a NaN/inf channel: counted and left out of the means
  double seconds = 0;                   // wall time: flatten, BVH build and rendering
  std::uint64_t rays = 0;               // rtcIntersect1 + rtcOccluded1 calls
};

// Renders scene.camera at options.width × options.height. Hidden instances are
// left out; lights are those of flatten_instances.
ReferenceResult render_reference(const Scene& scene, const ReferenceOptions& options);

// The same from already-flattened data (visible[i] != 0: instance i is drawn).
ReferenceResult render_reference(const FlatGeometry& geometry, const FlatInstances& instances,
                                 const std::vector<std::uint8_t>& visible, const GpuCamera& camera,
                                 const ReferenceOptions& options);

// Visibility bytes of a scene's instances, as the overload above takes them.
std::vector<std::uint8_t> instance_visibility(const Scene& scene);

}  // namespace gi
