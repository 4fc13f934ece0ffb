// The `bvh` backend's two-level structure on the CPU (docs/design.md §4): one
// binned-SAH BLAS per mesh over its object-space triangles, built once, and a
// TLAS over the visible instances, rebuilt when a transform or the visible
// set changes (never otherwise). gpu/bvh_buffers.* uploads what this builds;
// core/bvh/bvh_cpu_tracer.h traverses it on the CPU with the shader's code.
//
// Why two levels rather than one flattened tree: transform events then cost a
// TLAS over a handful of instances instead of a rebuild over every triangle,
// and rays meet triangles in object space exactly as ray queries do (same
// instance/primitive ids, the same t up to the transform's rounding), which is
// what the backend cross-check compares.
//
// Node array: [TLAS nodes: capacity | instance records: capacity | BLAS nodes].
// Node 0 is the TLAS root. The capacity grows (doubling) only when the
// instance count outgrows it; BLAS nodes then move (layout_generation()).
#pragma once
#include <cstdint>
#include <vector>

#include "core/bvh/bvh_builder.h"
#include "core/scene_flatten.h"
#include "core/shared/bvh_types.h"

namespace gi::bvh {

class SceneBvh {
 public:
  explicit SceneBvh(const FlatGeometry& geometry, const BuildOptions& blas_options = {});

  // Builds the BLASes of meshes appended to `geometry` since the last call
  // (the earlier meshes must be unchanged: scenario events only append) and
  // moves the node array (layout_generation()); the next update() rebuilds
  // the TLAS. Existing BLASes keep their bits.
  void add_meshes(const FlatGeometry& geometry);

  // visible[i]: instance i is drawn (a missing entry = visible). Instances
  // with no triangles are left out. Returns true if the TLAS was rebuilt.
  bool update(const std::vector<GpuInstance>& instances, const std::vector<bool>& visible);

  const std::vector<shader::BvhNode>& nodes() const { return nodes_; }
  const std::vector<shader::BvhTriangle>& triangles() const { return triangles_; }
  // Nodes [0, tlas_region_nodes()) change on a TLAS rebuild; the rest never.
  std::uint32_t tlas_region_nodes() const { return 2 * capacity_; }
  // Increments whenever the whole node array moved (capacity growth).
  std::uint32_t layout_generation() const { return layout_generation_; }
  std::uint32_t tlas_builds() const { return tlas_builds_; }
  std::uint32_t tlas_instance_count() const { return tlas_instance_count_; }
  std::uint32_t max_blas_depth() const { return max_blas_depth_; }

 private:
  void relayout(std::uint32_t capacity);

  BuildOptions blas_options_;
  std::vector<MeshRange> meshes_;
  std::vector<BuiltBvh> blas_;                 // per mesh, local refs
  std::vector<std::uint32_t> blas_triangle_base_;  // per mesh: first entry in triangles_
  std::vector<std::uint32_t> blas_node_offset_;    // per mesh: first node, relative to the BLAS region
  std::vector<shader::BvhNode> nodes_;
  std::vector<shader::BvhTriangle> triangles_;
  std::uint32_t capacity_ = 0;
  std::uint32_t layout_generation_ = 0;
  std::uint32_t tlas_builds_ = 0;
  std::uint32_t tlas_instance_count_ = 0;
  std::uint32_t max_blas_depth_ = 0;
  bool built_once_ = false;
  std::vector<shader::BvhNode> last_records_;  // instance records of the last TLAS build
};

}  // namespace gi::bvh
