// Embree 3 `rtcIntersect1` / `rtcOccluded1` over a flattened scene: the
// yardstick the `bvh` backend is measured against (docs/design.md §12: bvh ≥ 0.5×
// Embree rays/s) and the CPU oracle its CPU twin is tested against. World-space
// triangles, robust (watertight) mode, high build quality — as the reference
// path tracer builds its scene.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "core/bvh/ray_sets.h"
#include "core/scene_flatten.h"

namespace gi::bvh {

struct CastResult {
  bool hit = false;
  bool unoccluded = false;
  float t = 0.0f;
  std::uint32_t instance = 0, primitive = 0;
};

class EmbreeRayCaster {
 public:
  EmbreeRayCaster(const FlatGeometry& geometry, const FlatInstances& instances, const std::vector<bool>& visible);
  ~EmbreeRayCaster();
  EmbreeRayCaster(const EmbreeRayCaster&) = delete;
  EmbreeRayCaster& operator=(const EmbreeRayCaster&) = delete;

  CastResult closest(const TraceRay& ray) const;
  bool unoccluded(const TraceRay& ray) const;
  // Closest hits of all rays on `threads` threads (0 = all cores), for timing;
  // returns the number of hits.
  std::uint64_t closest_batch(const std::vector<TraceRay>& rays, unsigned threads) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gi::bvh
