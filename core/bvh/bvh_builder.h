// Binned-SAH BVH builder for the `bvh` tracing backend (DESIGN §4): a binary
// tree emitted in the two-box node layout of core/shared/bvh_types.h.
// Deterministic: serial, stable partitions, ties broken by primitive index,
// so the same boxes give the same bytes on every machine and thread count.
#pragma once
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/shared/bvh_types.h"

namespace gi::bvh {

struct Aabb {
  glm::vec3 lo{std::numeric_limits<float>::max()};
  glm::vec3 hi{-std::numeric_limits<float>::max()};
  void grow(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  float half_area() const {
    if (empty()) return 0.0f;
    const glm::vec3 e = hi - lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

struct BuildOptions {
  std::uint32_t max_leaf_size = 4;   // a leaf never holds more (SAH may stop earlier)
  std::uint32_t bins = 32;
  float traversal_cost = 1.0f;       // relative to one primitive test
  std::uint32_t max_depth = shader::BVH_BLAS_STACK_SIZE;  // deeper trees are refused (traversal stack)
};

// A built tree with *local* references: node 0 is the root; an inner child's
// ref indexes `nodes`, a leaf child's ref indexes `order` (the primitives in
// leaf order). A tree whose root would be a single leaf gets a root node with
// that leaf on the left and an empty right child, so traversal always starts
// at a node.
struct BuiltBvh {
  std::vector<shader::BvhNode> nodes;
  std::vector<std::uint32_t> order;  // order[k] = input primitive at leaf position k
  Aabb bounds;
  std::uint32_t depth = 0;           // inner nodes on the longest root-to-leaf path
};

// Throws gi::DeviceError if the tree would be deeper than options.max_depth.
BuiltBvh build_bvh(std::span<const Aabb> boxes, const BuildOptions& options = {});

// Copies `tree` into `out` with inner refs offset by node_base and leaf refs
// by leaf_base (empty children stay empty).
void append_relocated(const BuiltBvh& tree, std::uint32_t node_base, std::uint32_t leaf_base,
                      std::vector<shader::BvhNode>& out);

}  // namespace gi::bvh
