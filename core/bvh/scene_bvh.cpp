#include "core/bvh/scene_bvh.h"

#include <algorithm>
#include <cstring>
#include <map>

#include <fmt/format.h>
#include <glm/gtc/matrix_inverse.hpp>

#include "core/errors.h"

namespace gi::bvh {
namespace {

// The world box of an instance: its BLAS box's corners transformed, padded by
// a few float ulps of its magnitude so that the rounding of the ray's
// transformation into object space can never cull an instance that the
// object-space BLAS traversal would hit.
Aabb world_box(const Aabb& object_box, const glm::mat4& object_to_world) {
  Aabb box;
  for (int c = 0; c < 8; ++c) {
    const glm::vec3 p((c & 1) ? object_box.hi.x : object_box.lo.x, (c & 2) ? object_box.hi.y : object_box.lo.y,
                      (c & 4) ? object_box.hi.z : object_box.lo.z);
    box.grow(glm::vec3(object_to_world * glm::vec4(p, 1.0f)));
  }
  const glm::vec3 magnitude = glm::max(glm::abs(box.lo), glm::abs(box.hi));
  const float pad = 1e-5f * std::max({magnitude.x, magnitude.y, magnitude.z, 1e-3f});
  box.lo -= glm::vec3(pad);
  box.hi += glm::vec3(pad);
  return box;
}

}  // namespace

SceneBvh::SceneBvh(const FlatGeometry& geometry, const BuildOptions& blas_options) : blas_options_(blas_options) {
  add_meshes(geometry);
}

void SceneBvh::add_meshes(const FlatGeometry& geometry) {
  const std::size_t first = meshes_.size();
  for (std::size_t m = 0; m < first; ++m)
    if (m >= geometry.meshes.size() || meshes_[m] != geometry.meshes[m])
      throw DeviceError(fmt::format("SceneBvh::add_meshes: mesh {} changed; meshes may only be appended", m));
  if (first == geometry.meshes.size() && capacity_ > 0) return;
  std::uint32_t node_offset = blas_.empty() ? 0u : blas_node_offset_.back() + std::uint32_t(blas_.back().nodes.size());
  for (std::size_t m = first; m < geometry.meshes.size(); ++m) {
    const MeshRange& mesh = geometry.meshes[m];
    meshes_.push_back(mesh);
    blas_triangle_base_.push_back(std::uint32_t(triangles_.size()));
    blas_node_offset_.push_back(node_offset);
    std::vector<Aabb> boxes(mesh.triangle_count);
    std::vector<shader::BvhTriangle> tris(mesh.triangle_count);
    for (std::uint32_t t = 0; t < mesh.triangle_count; ++t) {
      shader::BvhTriangle& tri = tris[t];
      const std::uint32_t* idx = geometry.indices.data() + mesh.first_index + 3 * t;
      tri.p0 = glm::vec3(geometry.vertices[mesh.first_vertex + idx[0]].position);
      tri.p1 = glm::vec3(geometry.vertices[mesh.first_vertex + idx[1]].position);
      tri.p2 = glm::vec3(geometry.vertices[mesh.first_vertex + idx[2]].position);
      tri.primitive = t;
      boxes[t].grow(tri.p0);
      boxes[t].grow(tri.p1);
      boxes[t].grow(tri.p2);
    }
    BuiltBvh tree = build_bvh(boxes, blas_options_);
    for (std::uint32_t k : tree.order) triangles_.push_back(tris[k]);
    max_blas_depth_ = std::max(max_blas_depth_, tree.depth);
    node_offset += std::uint32_t(tree.nodes.size());
    blas_.push_back(std::move(tree));
  }
  // The new BLASes go after the others; the next update() rebuilds the TLAS.
  relayout(std::max<std::uint32_t>(capacity_, 1));
}

void SceneBvh::relayout(std::uint32_t capacity) {
  capacity_ = capacity;
  shader::BvhNode unused{};
  unused.child = glm::uvec4(shader::BVH_CHILD_EMPTY);
  nodes_.assign(2 * capacity_, unused);
  for (std::size_t m = 0; m < blas_.size(); ++m)
    append_relocated(blas_[m], 2 * capacity_ + blas_node_offset_[m], blas_triangle_base_[m], nodes_);
  ++layout_generation_;
  built_once_ = false;  // the records name BLAS roots that just moved
}

bool SceneBvh::update(const std::vector<GpuInstance>& instances, const std::vector<bool>& visible) {
  std::map<std::uint32_t, std::size_t> mesh_of_first_index;
  for (std::size_t m = 0; m < meshes_.size(); ++m)
    if (meshes_[m].triangle_count > 0) mesh_of_first_index[meshes_[m].first_index] = m;

  std::vector<std::pair<std::uint32_t, std::size_t>> drawn;  // (instance, mesh)
  for (std::uint32_t i = 0; i < instances.size(); ++i) {
    if (i < visible.size() && !visible[i]) continue;
    if (instances[i].triangle_count == 0) continue;
    const auto it = mesh_of_first_index.find(instances[i].first_index);
    if (it == mesh_of_first_index.end())
      throw DeviceError(fmt::format("instance {}: first_index {} matches no mesh", i, instances[i].first_index));
    drawn.emplace_back(i, it->second);
  }
  const std::uint32_t n = std::uint32_t(drawn.size());
  if (n > capacity_) relayout(std::max(n, 2 * capacity_));

  std::vector<shader::BvhNode> records;
  std::vector<Aabb> boxes;
  for (const auto& [i, mesh] : drawn) {
    const glm::mat4& m = instances[i].object_to_world;
    // Inverted in double: the object-space ray is then the correctly rounded
    // image of the world ray, as close to the ray-query backend's as floats allow.
    const glm::dmat4 inv = glm::inverse(glm::dmat4(m));
    shader::BvhInstance r{};
    r.world_to_object_c0 = glm::vec3(inv[0]);
    r.world_to_object_c1 = glm::vec3(inv[1]);
    r.world_to_object_c2 = glm::vec3(inv[2]);
    r.world_to_object_c3 = glm::vec3(inv[3]);
    r.blas_root = 2 * capacity_ + blas_node_offset_[mesh];
    r.instance = i;
    records.push_back(shader::bvh_node_from_instance(r));
    boxes.push_back(world_box(blas_[mesh].bounds, m));
  }

  const bool same = built_once_ && records.size() == last_records_.size() &&
                    (records.empty() ||
                     std::memcmp(records.data(), last_records_.data(), records.size() * sizeof(records[0])) == 0);
  if (same) return false;

  BuildOptions tlas_options;
  tlas_options.max_leaf_size = 1;
  tlas_options.stack_size = shader::BVH_TLAS_STACK_SIZE;
  const BuiltBvh tlas = build_bvh(boxes, tlas_options);
  shader::BvhNode unused{};
  unused.child = glm::uvec4(shader::BVH_CHILD_EMPTY);
  std::fill(nodes_.begin(), nodes_.begin() + 2 * capacity_, unused);
  std::vector<shader::BvhNode> tlas_nodes;
  append_relocated(tlas, 0, capacity_, tlas_nodes);
  std::copy(tlas_nodes.begin(), tlas_nodes.end(), nodes_.begin());
  for (std::uint32_t k = 0; k < tlas.order.size(); ++k) nodes_[capacity_ + k] = records[tlas.order[k]];

  last_records_ = std::move(records);
  built_once_ = true;
  tlas_instance_count_ = n;
  ++tlas_builds_;
  return true;
}

}  // namespace gi::bvh
