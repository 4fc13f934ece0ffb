#include "core/reference/embree_geometry.h"

#include <algorithm>

namespace gi {

bool attach_instance_geometry(RTCDevice device, RTCScene scene, const FlatGeometry& g, const GpuInstance& inst,
                              std::uint32_t index) {
  const std::uint32_t* idx = g.indices.data() + inst.first_index;
  std::uint32_t vertex_count = 0;
  for (std::uint32_t k = 0; k < 3 * inst.triangle_count; ++k) vertex_count = std::max(vertex_count, idx[k] + 1);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(
      rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertex_count));
  auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), inst.triangle_count));
  if (!vb || !ib) {
    rtcReleaseGeometry(geom);
    return false;
  }
  for (std::uint32_t v = 0; v < vertex_count; ++v) {
    const glm::vec3 p = glm::vec3(inst.object_to_world * g.vertices[inst.first_vertex + v].position);
    vb[3 * v + 0] = p.x;
    vb[3 * v + 1] = p.y;
    vb[3 * v + 2] = p.z;
  }
  std::copy(idx, idx + 3 * inst.triangle_count, ib);
  rtcCommitGeometry(geom);
  rtcAttachGeometryByID(scene, geom, index);
  rtcReleaseGeometry(geom);
  return true;
}

}  // namespace gi
