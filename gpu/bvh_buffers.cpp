#include "gpu/bvh_buffers.h"

#include <cstring>

#include <spdlog/spdlog.h>

namespace gi::gpu {

std::vector<ShaderDefine> trace_backend_defines(const Device& device) {
  if (device.backend() != TraceBackend::bvh) return {};
  // On a CPU device (lavapipe) the shader compiler's time is what counts: the
  // one-loop traversal compiles in three quarters of the time; on a GPU the
  // loop per level runs faster (core/shared/bvh_traverse.h). Same bits.
  if (device.info().device_type == "cpu") return {{"TRACE_BACKEND_BVH", ""}, {"BVH_TRAVERSAL_ONE_LOOP", ""}};
  return {{"TRACE_BACKEND_BVH", ""}};
}

BvhBuffers::BvhBuffers(Device& device, const FlatGeometry& geometry) : device_(device), bvh_(geometry) {
  upload_all();
  spdlog::debug("bvh: {} triangles, {} nodes, deepest BLAS {} levels", bvh_.triangles().size(), bvh_.nodes().size(),
                bvh_.max_blas_depth());
}

void BvhBuffers::upload_all() {
  const VkDeviceSize node_bytes = bvh_.nodes().size() * sizeof(shader::BvhNode);
  const VkDeviceSize tri_bytes = bvh_.triangles().size() * sizeof(shader::BvhTriangle);
  if (!nodes_ || nodes_.size() < node_bytes) {
    nodes_ = Buffer(device_, node_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "bvh nodes");
    buffers_changed_ = true;
  }
  if (!triangles_ || triangles_.size() < tri_bytes) {
    triangles_ = Buffer(device_, tri_bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "bvh triangles");
    buffers_changed_ = true;
  }
  if (bvh_.triangles().size() != uploaded_triangles_) {  // BLAS triangles only change when meshes are added
    if (tri_bytes) triangles_.upload(bvh_.triangles());
    uploaded_triangles_ = bvh_.triangles().size();
  }
  nodes_.upload(bvh_.nodes());
  uploaded_generation_ = bvh_.layout_generation();
}

void BvhBuffers::add_meshes(const FlatGeometry& geometry) {
  bvh_.add_meshes(geometry);
  upload_all();
}

bool BvhBuffers::update(const std::vector<GpuInstance>& instances, const std::vector<bool>& visible) {
  const bool rebuilt = bvh_.update(instances, visible);
  if (rebuilt) upload_tlas();
  if (keep_previous_ && !previous_uploaded_) sync_previous();  // the first frame's
  return rebuilt;
}

void BvhBuffers::end_frame() {
  if (keep_previous_) sync_previous();
}

void BvhBuffers::sync_previous() {
  const std::vector<shader::BvhNode>& now = bvh_.nodes();
  if (previous_uploaded_ && now.size() == previous_.size() &&
      std::memcmp(now.data(), previous_.data(), now.size() * sizeof(now[0])) == 0)
    return;
  const VkDeviceSize bytes = now.size() * sizeof(shader::BvhNode);
  if (!previous_nodes_ || previous_nodes_.size() < bytes) {
    previous_nodes_ = Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "previous bvh nodes");
    buffers_changed_ = true;
  }
  previous_nodes_.upload(now);
  previous_ = now;
  previous_uploaded_ = true;
}

void BvhBuffers::upload_tlas() {
  if (bvh_.layout_generation() != uploaded_generation_) {
    upload_all();  // the TLAS region grew: every BLAS node moved
  } else {
    const std::span<const shader::BvhNode> region(bvh_.nodes().data(), bvh_.tlas_region_nodes());
    nodes_.upload(region);
  }
}

}  // namespace gi::gpu
