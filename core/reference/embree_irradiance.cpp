#include "core/reference/embree_irradiance.h"

#include <string>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/errors.h"
#include "core/reference/embree_geometry.h"
#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"
#include "core/shared/scene_types.h"

namespace gi::shader {
namespace {

// The scene accessors and Embree ray casts the shared integrator needs, as
// in embree_reference.cpp (its bridge is private to that file).
struct IrradianceBridge {
  const GpuInstance* instances = nullptr;
  const GpuMaterial* materials = nullptr;
  const GpuVertex* vertices = nullptr;
  const uint* indices = nullptr;
  const GpuLight* lights = nullptr;
  uint light_count = 0;
  uint directional_count = 0;
  RTCScene rtc = nullptr;

  GpuInstance scene_instance(uint i) const { return instances[i]; }
  GpuMaterial scene_material(uint i) const { return materials[i]; }
  GpuVertex scene_vertex(uint i) const { return vertices[i]; }
  uint scene_index(uint i) const { return indices[i]; }
  GpuLight scene_light(uint i) const { return lights[i]; }
  uint scene_light_count() const { return light_count; }
  uint scene_directional_light_count() const { return directional_count; }

  bool trace_closest(vec3 origin, vec3 dir, float tmax, Hit& hit) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tfar = tmax;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rtc, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.instance = rh.hit.geomID;
    hit.primitive = rh.hit.primID;
    hit.barycentrics = vec2(rh.hit.u, rh.hit.v);
    return true;
  }

  bool trace_unoccluded(vec3 origin, vec3 dir, float tmax) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = origin.x;
    ray.org_y = origin.y;
    ray.org_z = origin.z;
    ray.dir_x = dir.x;
    ray.dir_y = dir.y;
    ray.dir_z = dir.z;
    ray.tfar = tmax;
    ray.mask = 0xFFFFFFFFu;
    rtcOccluded1(rtc, &context, &ray);
    return !(ray.tfar < 0.0f);
  }

#include "core/shared/scene_access.h"
#include "core/shared/path_integrator.h"
};

// Irradiance estimates use their own stream, apart from the images'.
constexpr uint RNG_DOMAIN_EMBREE_IRRADIANCE = 0xC2B2AE35u;

}  // namespace
}  // namespace gi::shader

namespace gi {

std::vector<glm::vec3> embree_irradiance(const FlatGeometry& g, const FlatInstances& f,
                                         const std::vector<std::uint8_t>& visible,
                                         const std::vector<IrradiancePoint>& points, const IrradianceOptions& o) {
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw DeviceError("Embree: rtcNewDevice failed");
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  for (std::uint32_t i = 0; i < f.instances.size(); ++i) {
    if (i >= visible.size() || !visible[i] || f.instances[i].triangle_count == 0) continue;
    if (!attach_instance_geometry(device, scene, g, f.instances[i], i)) {
      rtcReleaseScene(scene);
      rtcReleaseDevice(device);
      throw DeviceError("Embree: cannot allocate buffers");
    }
  }
  tbb::task_arena serial(1);  // the BVH (and ties between equal hits) independent of threads
  serial.execute([&] { rtcCommitScene(scene); });

  shader::IrradianceBridge proto;
  proto.instances = f.instances.data();
  proto.materials = f.materials.data();
  proto.vertices = g.vertices.data();
  proto.indices = g.indices.data();
  proto.lights = f.lights.data();
  proto.light_count = static_cast<std::uint32_t>(f.lights.size());
  proto.directional_count = f.directional_light_count;
  proto.rtc = scene;

  std::vector<glm::vec3> out(points.size(), glm::vec3(0.0f));
  tbb::task_arena arena(o.threads ? int(o.threads) : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const tbb::blocked_range<std::size_t>& r) {
      shader::IrradianceBridge bridge = proto;
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
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return out;
}

}  // namespace gi
