// Compares two backends' results for the same ray list (tests only): the
// figures the backend cross-check asserts on.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "gpu/passes/ray_list_trace_types.h"

namespace gi::test {

struct BackendComparison {
  std::uint32_t hit_mismatches = 0;        // closest hit found by one only
  std::uint32_t occlusion_mismatches = 0;  // trace_unoccluded differs
  std::uint32_t primitive_mismatches = 0;  // both hit, other instance/triangle (ties on shared edges)
  double max_relative_dt = 0.0;            // over rays both hit: |ta − tb| / max(ta, tb)
  // The same with the ray origin's magnitude as a floor of the denominator:
  // |Δt| / max(t, |origin|∞). A hit a few µm from an origin 1 m from the world
  // origin carries float rounding of ~1e-7 m in either backend, so its plain
  // relative Δt says nothing about the tracer; this one does.
  double max_scaled_dt = 0.0;
  std::uint32_t relative_dt_above_1e4 = 0;  // rays whose plain relative Δt exceeds 1e-4
};

inline BackendComparison compare_backends(const std::vector<shader::TestResult>& a,
                                          const std::vector<shader::TestResult>& b,
                                          const std::vector<shader::TestRay>& rays = {}) {
  BackendComparison c;
  const std::size_t n = std::min(a.size(), b.size());
  c.hit_mismatches = std::uint32_t(std::max(a.size(), b.size()) - n);
  for (std::size_t i = 0; i < n; ++i) {
    const bool ha = a[i].flags & 1u, hb = b[i].flags & 1u;
    if (ha != hb) ++c.hit_mismatches;
    if ((a[i].flags & 2u) != (b[i].flags & 2u)) ++c.occlusion_mismatches;
    if (ha && hb) {
      if (a[i].instance != b[i].instance || a[i].primitive != b[i].primitive) ++c.primitive_mismatches;
      const double ta = a[i].t, tb = b[i].t;
      const double rel = std::abs(ta - tb) / std::max({std::abs(ta), std::abs(tb), 1e-30});
      c.max_relative_dt = std::max(c.max_relative_dt, std::isfinite(rel) ? rel : 1e30);
      c.relative_dt_above_1e4 += !(rel <= 1e-4);
      const double scale = i < rays.size() ? std::max({std::abs(rays[i].origin_tmax.x), std::abs(rays[i].origin_tmax.y),
                                                       std::abs(rays[i].origin_tmax.z)})
                                           : 0.0;
      const double scaled = std::abs(ta - tb) / std::max({std::abs(ta), std::abs(tb), scale, 1e-30});
      c.max_scaled_dt = std::max(c.max_scaled_dt, std::isfinite(scaled) ? scaled : 1e30);
    }
  }
  return c;
}

}  // namespace gi::test
