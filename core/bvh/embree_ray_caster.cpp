#include "core/reference/embree_geometry.h"
#include "core/bvh/embree_ray_caster.h"

#include <algorithm>
#include <atomic>
#include <string>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/errors.h"

namespace gi::bvh {

struct EmbreeRayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

EmbreeRayCaster::EmbreeRayCaster(const FlatGeometry& g, const FlatInstances& f, const std::vector<bool>& visible)
    : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw DeviceError("Embree: rtcNewDevice failed");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  for (std::uint32_t i = 0; i < f.instances.size(); ++i) {
    if (i < visible.size() && !visible[i]) continue;
    const GpuInstance& inst = f.instances[i];
    if (inst.triangle_count == 0) continue;
    if (!attach_instance_geometry(impl_->device, impl_->scene, g, inst, i))
      throw DeviceError("Embree: cannot allocate geometry buffers");
  }
  rtcCommitScene(impl_->scene);
}

EmbreeRayCaster::~EmbreeRayCaster() = default;

CastResult EmbreeRayCaster::closest(const TraceRay& r) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = r.origin.x;
  rh.ray.org_y = r.origin.y;
  rh.ray.org_z = r.origin.z;
  rh.ray.dir_x = r.direction.x;
  rh.ray.dir_y = r.direction.y;
  rh.ray.dir_z = r.direction.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = r.tmax;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  CastResult c;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return c;
  c.hit = true;
  c.t = rh.ray.tfar;
  c.instance = rh.hit.geomID;
  c.primitive = rh.hit.primID;
  return c;
}

bool EmbreeRayCaster::unoccluded(const TraceRay& r) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = r.origin.x;
  ray.org_y = r.origin.y;
  ray.org_z = r.origin.z;
  ray.dir_x = r.direction.x;
  ray.dir_y = r.direction.y;
  ray.dir_z = r.direction.z;
  ray.tnear = 0.0f;
  ray.tfar = r.tmax;
  ray.mask = 0xFFFFFFFFu;
  rtcOccluded1(impl_->scene, &context, &ray);
  return !(ray.tfar < 0.0f);
}

std::uint64_t EmbreeRayCaster::closest_batch(const std::vector<TraceRay>& rays, unsigned threads) const {
  std::atomic<std::uint64_t> hits{0};
  tbb::task_arena arena(threads == 0 ? tbb::task_arena::automatic : int(threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 256), [&](const auto& range) {
      std::uint64_t local = 0;
      for (std::size_t i = range.begin(); i != range.end(); ++i) local += closest(rays[i]).hit ? 1 : 0;
      hits += local;
    });
  });
  return hits.load();
}

}  // namespace gi::bvh
