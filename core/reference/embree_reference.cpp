#include "core/reference/embree_reference.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/errors.h"
#include "core/reference/embree_bridge.h"
#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"
#include "core/shared/scene_types.h"

namespace gi {
namespace {

constexpr std::uint32_t kTile = 16;

}  // namespace

std::vector<std::uint8_t> instance_visibility(const Scene& scene) {
  const std::vector<bool> visible = scene.visible_instances();
  return {visible.begin(), visible.end()};
}

ReferenceResult render_reference(const FlatGeometry& geometry, const FlatInstances& flat,
                                 const std::vector<std::uint8_t>& visible, const GpuCamera& camera,
                                 const ReferenceOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  ReferenceResult r;
  r.mean = Image(o.width, o.height);
  r.half_a = Image(o.width, o.height);
  r.half_b = Image(o.width, o.height);
  if (o.width == 0 || o.height == 0) return r;

  EmbreeScene embree(geometry, flat, visible);
  const shader::EmbreeBridge proto = shader::EmbreeBridge::over(geometry, flat, embree.scene());

  std::atomic<std::uint64_t> rays{0}, nonfinite{0};
  const glm::vec3 origin = glm::vec3(camera.position);
  const glm::uvec2 resolution(o.width, o.height);

  auto render_tile = [&](const tbb::blocked_range2d<std::uint32_t>& tile) {
    shader::EmbreeBridge bridge = proto;
    std::uint64_t bad = 0;
    for (std::uint32_t y = tile.rows().begin(); y < tile.rows().end(); ++y) {
      for (std::uint32_t x = tile.cols().begin(); x < tile.cols().end(); ++x) {
        const std::uint32_t pixel = y * o.width + x;
        const glm::vec3 dir = shader::camera_ray_direction(camera, glm::uvec2(x, y), resolution);
        // Every sample of a pixel shares its camera ray, so the background
        // (seen, never lighting anything) is one test per pixel.
        glm::vec3 background(0.0f);
        if (o.background != glm::vec3(0.0f)) {
          shader::Hit primary;
          if (!bridge.trace_closest(origin, dir, shader::RAY_TMAX, primary)) background = o.background;
        }
        // Each pixel sums its own samples in sample order: no cross-thread sums.
        glm::dvec3 sum[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
        std::uint64_t count[2] = {0, 0};
        for (std::uint32_t s = 0; s < o.spp; ++s) {
          const std::uint32_t sample = o.first_sample + s;
          std::uint32_t rng = shader::rng_seed(o.seed, shader::RNG_DOMAIN_EMBREE, pixel, sample);
          const glm::vec3 L = o.direct_only ? bridge.direct_trace(origin, dir, rng)
                                            : bridge.path_trace(origin, dir, rng, o.max_bounces);
          if (!std::isfinite(L.x) || !std::isfinite(L.y) || !std::isfinite(L.z)) {
            ++bad;
            continue;
          }
          sum[sample & 1u] += glm::dvec3(L);
          ++count[sample & 1u];
        }
        const std::size_t i = pixel;
        if (count[0]) r.half_a.pixels[i] = glm::vec3(sum[0] / double(count[0])) + background;
        if (count[1]) r.half_b.pixels[i] = glm::vec3(sum[1] / double(count[1])) + background;
        if (count[0] + count[1])
          r.mean.pixels[i] = glm::vec3((sum[0] + sum[1]) / double(count[0] + count[1])) + background;
      }
    }
    rays.fetch_add(bridge.rays, std::memory_order_relaxed);
    nonfinite.fetch_add(bad, std::memory_order_relaxed);
  };

  const tbb::blocked_range2d<std::uint32_t> all(0, o.height, kTile, 0, o.width, kTile);
  if (o.threads == 0) {
    tbb::parallel_for(all, render_tile);
  } else {
    tbb::task_arena arena(static_cast<int>(o.threads));
    arena.execute([&] { tbb::parallel_for(all, render_tile); });
  }

  r.rays = rays.load();
  r.nonfinite_samples = nonfinite.load();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

ReferenceResult render_reference(const Scene& scene, const ReferenceOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const FlatGeometry geometry = flatten_geometry(scene);
  const FlatInstances flat = flatten_instances(scene, geometry);
  const GpuCamera camera = make_gpu_camera(scene.camera, std::max(options.width, 1u), std::max(options.height, 1u));
  ReferenceOptions o = options;
  o.background = scene.background;
  ReferenceResult r = render_reference(geometry, flat, instance_visibility(scene), camera, o);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace gi
