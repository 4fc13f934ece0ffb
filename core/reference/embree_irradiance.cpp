#include "core/reference/embree_irradiance.h"

#include <string>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/errors.h"
#include "core/reference/embree_bridge.h"
#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"
#include "core/shared/scene_types.h"

namespace gi::shader {
namespace {

// Irradiance estimates use their own stream, apart from the images'.
constexpr uint RNG_DOMAIN_EMBREE_IRRADIANCE = 0xC2B2AE35u;

}  // namespace
}  // namespace gi::shader

namespace gi {

std::vector<glm::vec3> embree_irradiance(const FlatGeometry& g, const FlatInstances& f,
                                         const std::vector<std::uint8_t>& visible,
                                         const std::vector<IrradiancePoint>& points, const IrradianceOptions& o) {
  const EmbreeScene embree(g, f, visible);
  const shader::EmbreeBridge proto = shader::EmbreeBridge::over(g, f, embree.scene());

  std::vector<glm::vec3> out(points.size(), glm::vec3(0.0f));
  tbb::task_arena arena(o.threads ? int(o.threads) : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& r) {
      shader::EmbreeBridge bridge = proto;
      for (std::size_t i = r.begin(); i < r.end(); ++i) {
        const IrradiancePoint& p = points[i];
        const glm::vec3 origin = bridge.offset_ray_origin(p.position, p.normal);
        // Sum in double in sample order: the same bits at any thread count.
        glm::dvec3 sum(0.0);
        for (std::uint32_t s = 0; s < o.samples; ++s) {
          std::uint32_t rng = shader::rng_seed(o.seed, shader::RNG_DOMAIN_EMBREE_IRRADIANCE, std::uint32_t(i), s);
          const glm::vec3 dir = shader::to_world(shader::sample_cosine_hemisphere(shader::rng_next_vec2(rng)), p.normal);
          sum += glm::dvec3(bridge.path_trace(origin, dir, rng, o.max_bounces));
        }
        // Cosine sampling: E = π · mean(L).
        out[i] = glm::vec3(sum * (double(shader::PI) / double(std::max(o.samples, 1u))));
      }
    });
  });
  return out;
}

}  // namespace gi
