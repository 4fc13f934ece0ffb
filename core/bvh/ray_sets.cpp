#include "core/bvh/ray_sets.h"

#include <algorithm>

#include "core/shared/rng.h"
#include "core/shared/sampling.h"

namespace gi::bvh {
namespace {

struct WorldTriangle {
  glm::vec3 p0, p1, p2;
};

std::vector<WorldTriangle> visible_triangles(const FlatGeometry& g, const FlatInstances& f,
                                             const std::vector<bool>& visible) {
  std::vector<WorldTriangle> out;
  for (std::size_t i = 0; i < f.instances.size(); ++i) {
    if (i < visible.size() && !visible[i]) continue;
    const GpuInstance& inst = f.instances[i];
    for (std::uint32_t t = 0; t < inst.triangle_count; ++t) {
      const std::uint32_t* idx = g.indices.data() + inst.first_index + 3 * t;
      auto p = [&](int k) {
        return glm::vec3(inst.object_to_world * g.vertices[inst.first_vertex + idx[k]].position);
      };
      out.push_back({p(0), p(1), p(2)});
    }
  }
  return out;
}

}  // namespace

std::vector<TraceRay> make_ray_set(const FlatGeometry& geometry, const FlatInstances& instances,
                                   const std::vector<bool>& visible, const RaySetOptions& o) {
  const std::vector<WorldTriangle> tris = visible_triangles(geometry, instances, visible);
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const auto& t : tris)
    for (const glm::vec3& p : {t.p0, t.p1, t.p2}) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  if (tris.empty()) lo = hi = glm::vec3(0.0f);
  const glm::vec3 extent = hi - lo;
  const float diagonal = std::max(glm::length(extent), 1e-3f);
  const float offset = 1e-4f * diagonal;  // leave the surface, as offset_ray_origin does for the integrator

  std::vector<TraceRay> rays;
  rays.reserve(o.count);
  for (std::uint32_t i = 0; i < o.count; ++i) {
    shader::uint state = shader::rng_seed(o.seed, 0x7e57u, i, 0u);
    RayKind kind = o.kind;
    if (kind == RayKind::mixed) kind = RayKind(i % 3);
    TraceRay r{};
    r.tmax = shader::RAY_TMAX;
    if (kind == RayKind::camera || tris.empty()) {
      const glm::vec2 u = shader::rng_next_vec2(state);
      const glm::vec2 ndc = u * 2.0f - glm::vec2(1.0f);
      r.origin = glm::vec3(o.camera.position);
      r.direction = glm::normalize(glm::vec3(o.camera.forward) + ndc.x * glm::vec3(o.camera.right) -
                                   ndc.y * glm::vec3(o.camera.up));
    } else if (kind == RayKind::diffuse) {
      const WorldTriangle& t = tris[shader::rng_next_uint(state) % tris.size()];
      const glm::vec2 b = shader::sample_triangle(shader::rng_next_vec2(state));
      const glm::vec3 p = (1.0f - b.x - b.y) * t.p0 + b.x * t.p1 + b.y * t.p2;
      glm::vec3 n = glm::cross(t.p1 - t.p0, t.p2 - t.p0);
      const float len = glm::length(n);
      n = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
      if (shader::rng_next_float(state) < 0.5f) n = -n;  // surfaces are two-sided
      r.origin = p + offset * n;
      r.direction = glm::normalize(shader::to_world(shader::sample_cosine_hemisphere(shader::rng_next_vec2(state)), n));
    } else {
      const glm::vec3 a = lo + extent * glm::vec3(shader::rng_next_float(state), shader::rng_next_float(state),
                                                  shader::rng_next_float(state));
      const glm::vec3 b = lo + extent * glm::vec3(shader::rng_next_float(state), shader::rng_next_float(state),
                                                  shader::rng_next_float(state));
      const glm::vec3 d = b - a;
      r.origin = a;
      r.direction = glm::length(d) > 0.0f ? glm::normalize(d) : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    if (o.kind == RayKind::mixed && i % 10 == 9) r.tmax = diagonal * shader::rng_next_float(state);
    rays.push_back(r);
  }
  return rays;
}

}  // namespace gi::bvh
