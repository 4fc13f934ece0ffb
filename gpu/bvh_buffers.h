// The `bvh` tracing backend on the GPU (docs/design.md §4): the CPU-built two-level
// BVH (core/bvh/scene_bvh.h) in two storage buffers that
// gpu/shaders/trace_bvh.glsl traverses. The BLASes are uploaded once (and
// again when meshes are added); a TLAS rebuild rewrites only the TLAS region
// of the node buffer.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "core/bvh/scene_bvh.h"
#include "core/scene_flatten.h"
#include "gpu/buffer.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"

namespace gi::gpu {

// The defines that select a backend's trace_closest/trace_unoccluded in
// gpu/shaders/scene_bindings.glsl: TRACE_BACKEND_BVH for bvh (with
// BVH_TRAVERSAL_ONE_LOOP on CPU devices), none for rayquery.
std::vector<ShaderDefine> trace_backend_defines(const Device& device);

class BvhBuffers {
 public:
  BvhBuffers(Device& device, const FlatGeometry& geometry);

  // Meshes appended to the geometry (a spawn of a generated mesh): their
  // BLASes are built and the buffers re-uploaded (grown when needed); the
  // next update() rebuilds the TLAS. Earlier meshes must be unchanged.
  void add_meshes(const FlatGeometry& geometry);

  // As AccelerationStructures::update: rebuilds the TLAS only if the visible
  // set or a visible transform changed. Returns true if it rebuilt.
  bool update(const std::vector<GpuInstance>& instances, const std::vector<bool>& visible);

  // As AccelerationStructures::keep_previous_tlas and end_frame: a second
  // node buffer holds the previous frame's node array (BLASes included, so a
  // relayout cannot mix frames; the triangles are shared, append-only).
  void keep_previous_nodes() { keep_previous_ = true; }
  void end_frame();
  const Buffer& previous_nodes() const { return previous_nodes_; }

  const Buffer& nodes() const { return nodes_; }
  const Buffer& triangles() const { return triangles_; }
  // True once after the buffers were replaced: descriptors must be rewritten.
  bool take_buffers_changed() { return std::exchange(buffers_changed_, false); }
  std::uint32_t tlas_builds() const { return bvh_.tlas_builds(); }
  const bvh::SceneBvh& scene_bvh() const { return bvh_; }

 private:
  void upload_all();

  Device& device_;
  bvh::SceneBvh bvh_;
  void sync_previous();
  void upload_tlas();  // after a TLAS rebuild

  Buffer nodes_, triangles_, previous_nodes_;
  std::vector<shader::BvhNode> previous_;  // what previous_nodes_ holds
  bool keep_previous_ = false, previous_uploaded_ = false;
  std::uint32_t uploaded_generation_ = 0;
  std::size_t uploaded_triangles_ = 0;
  bool buffers_changed_ = true;
};

}  // namespace gi::gpu
