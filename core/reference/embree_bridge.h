// The CPU side of the shared integrators: scene accessors over the flat
// arrays and Embree ray casts, into whose body the shared surface
// reconstruction and integrators are included, so they become its member
// functions (core/shared/scene_access.h). One bridge for the Embree
// reference image and the irradiance reference, so both trace exactly as
// the shaders shade.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "core/scene_flatten.h"
#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"
#include "core/shared/scene_types.h"

namespace gi {

// Owns an Embree device and a scene of the visible instances (geomID ==
// instance index), robust traversal, built single-threaded: the BVH, and so
// every tie between equal-t hits, cannot depend on the thread count.
// DeviceError when Embree fails.
class EmbreeScene {
 public:
  EmbreeScene(const FlatGeometry& geometry, const FlatInstances& flat, const std::vector<std::uint8_t>& visible);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  RTCScene scene() const { return scene_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::string error_;  // the first error Embree reported
};

}  // namespace gi

namespace gi::shader {

// Copied per task (rays counts per copy, summed as integers by the caller).
struct EmbreeBridge {
  // Over the flat arrays (which must outlive it) and an Embree scene of them.
  static EmbreeBridge over(const FlatGeometry& geometry, const FlatInstances& flat, RTCScene scene) {
    EmbreeBridge b;
    b.instances = flat.instances.data();
    b.materials = flat.materials.data();
    b.vertices = geometry.vertices.data();
    b.indices = geometry.indices.data();
    b.lights = flat.lights.data();
    b.light_count = static_cast<uint>(flat.lights.size());
    b.directional_count = flat.directional_light_count;
    b.vertex_attributes = geometry.vertex_attributes.data();
    b.material_textures = flat.material_textures.data();
    b.texture_images = geometry.texture_images.data();
    b.texels = geometry.texels.data();
    b.rtc = scene;
    return b;
  }

  const GpuInstance* instances = nullptr;
  const GpuMaterial* materials = nullptr;
  const GpuVertex* vertices = nullptr;
  const uint* indices = nullptr;
  const GpuLight* lights = nullptr;
  const GpuVertexAttributes* vertex_attributes = nullptr;
  const GpuMaterialTextures* material_textures = nullptr;
  const GpuTextureImage* texture_images = nullptr;
  const uint* texels = nullptr;
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
  GpuVertexAttributes scene_vertex_attributes(uint i) const { return vertex_attributes[i]; }
  GpuMaterialTextures scene_material_textures(uint i) const { return material_textures[i]; }
  GpuTextureImage scene_texture_image(uint i) const { return texture_images[i]; }
  uint scene_texel(uint i) const { return texels[i]; }

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


}  // namespace gi::shader
