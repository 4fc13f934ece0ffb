#include "core/reference/embree_geometry.h"
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
#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"
#include "core/shared/scene_types.h"

namespace gi::shader {
namespace {

// The bridge: scene accessors over the flat arrays and Embree ray casts; the
// shared surface reconstruction and path tracer are included into its body
// and become member functions (see core/shared/scene_access.h).
struct EmbreeBridge {
  const GpuInstance* instances = nullptr;
  const GpuMaterial* materials = nullptr;
  const GpuVertex* vertices = nullptr;
  const uint* indices = nullptr;
  const GpuLight* lights = nullptr;
  uint light_count = 0;
  uint directional_count = 0;
  RTCScene rtc = nullptr;
  std::uint64_t rays = 0;  // per bridge (one per tile): summed as integers

  GpuInstance scene_instance(uint i) const { return instances[i]; }
  GpuMaterial scene_material(uint i) const { return materials[i]; }
  GpuVertex scene_vertex(uint i) const { return vertices[i]; }
  uint scene_index(uint i) const { return indices[i]; }
  GpuLight scene_light(uint i) const { return lights[i]; }
  uint scene_light_count() const { return light_count; }
  uint scene_directional_light_count() const { return directional_count; }

  bool trace_closest(vec3 origin, vec3 dir, float tmax, Hit& hit) {
    ++rays;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh;
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.tnear = 0.0f;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.time = 0.0f;
    rh.ray.tfar = tmax;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rtc, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.instance = rh.hit.geomID;  // geometries are attached with ID = instance index
    hit.primitive = rh.hit.primID;
    hit.barycentrics = vec2(rh.hit.u, rh.hit.v);
    return true;
  }

  bool trace_unoccluded(vec3 origin, vec3 dir, float tmax) {
    ++rays;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray;
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    ray.tnear = 0.0f;
    ray.dir_x = dir.x;
    ray.dir_y = dir.y;
    ray.dir_z = dir.z;
    ray.time = 0.0f;
    ray.tfar = tmax;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(rtc, &context, &ray);
    return !(ray.tfar < 0.0f);  // Embree sets tfar = -inf on a hit
  }

#include "core/shared/scene_access.h"
#include "core/shared/path_integrator.h"
#include "core/shared/direct_integrator.h"
};

}  // namespace
}  // namespace gi::shader

namespace gi {
namespace {

struct EmbreeError {
  std::string message;
};

void embree_error(void* user, RTCError code, const char* str) {
  auto* e = static_cast<EmbreeError*>(user);
  if (e->message.empty()) e->message = "Embree error " + std::to_string(int(code)) + ": " + (str ? str : "");
}

// Owns an Embree device and scene built from the flat arrays.
class EmbreeScene {
 public:
  EmbreeScene(const FlatGeometry& g, const FlatInstances& f, const std::vector<std::uint8_t>& visible) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw DeviceError("Embree: rtcNewDevice failed (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(device_, embree_error, &error_);
    scene_ = rtcNewScene(device_);
    // Robust (watertight) traversal: no leaks through shared edges.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    for (std::uint32_t i = 0; i < f.instances.size(); ++i) {
      if (i >= visible.size() || !visible[i]) continue;
      const shader::GpuInstance& inst = f.instances[i];
      if (inst.triangle_count == 0) continue;
      if (!attach_instance_geometry(device_, scene_, g, inst, i))  // geomID == instance index
        throw DeviceError("Embree: cannot allocate buffers: " + error_.message);
    }
    // A single-threaded build: the BVH (and so every tie between equal-t hits)
    // cannot depend on the thread count.
    tbb::task_arena serial(1);
    serial.execute([&] { rtcCommitScene(scene_); });
    if (!error_.message.empty()) throw DeviceError(error_.message);
  }
  ~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  RTCScene scene() const { return scene_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  EmbreeError error_;
};

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
  shader::EmbreeBridge proto;
  proto.instances = flat.instances.data();
  proto.materials = flat.materials.data();
  proto.vertices = geometry.vertices.data();
  proto.indices = geometry.indices.data();
  proto.lights = flat.lights.data();
  proto.light_count = static_cast<std::uint32_t>(flat.lights.size());
  proto.directional_count = flat.directional_light_count;
  proto.rtc = embree.scene();

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
        if (count[0]) r.half_a.pixels[i] = glm::vec3(sum[0] / double(count[0]));
        if (count[1]) r.half_b.pixels[i] = glm::vec3(sum[1] / double(count[1]));
        if (count[0] + count[1]) r.mean.pixels[i] = glm::vec3((sum[0] + sum[1]) / double(count[0] + count[1]));
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
  ReferenceResult r = render_reference(geometry, flat, instance_visibility(scene), camera, options);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace gi
