// Binned-SAH BVH builder for the `bvh` tracing backend (docs/design.md §4): a binary
// SAH tree, collapsed to the 4-wide node layout of core/shared/bvh_types.h.
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
  std::uint32_t max_leaf_size = 4;   // a leaf never holds more (SAH may stop earlier); at most BVH_MAX_LEAF_SIZE
  std::uint32_t bins = 32;
  float traversal_cost = 1.0f;       // relative to one primitive test
  std::uint32_t stack_size = shader::BVH_BLAS_STACK_SIZE;  // trees needing a deeper traversal stack are refused
};

// A built tree with *local* references: node 0 is the root; an inner child
// indexes `nodes`, a leaf child's first entry indexes `order` (the primitives
// in leaf order). A tree whose root would be a single leaf gets a root node
// with that leaf as child 0 and the rest empty, so traversal always starts at
// a node.
struct BuiltBvh {
  std::vector<shader::BvhNode> nodes;
  std::vector<std::uint32_t> order;  // order[k] = input primitive at leaf position k
  Aabb bounds;
  std::uint32_t depth = 0;           // binary inner nodes on the longest root-to-leaf path
  std::uint32_t stack_need = 0;      // traversal stack entries the 4-wide tree can need
};

// Throws gi::DeviceError if traversing the tree could need more than
// options.stack_size stack entries.
BuiltBvh build_bvh(std::span<const Aabb> boxes, const BuildOptions& options = {});

// Copies `tree` into `out` with inner children offset by node_base and leaf
// first entries by leaf_base (empty children stay empty).
void append_relocated(const BuiltBvh& tree, std::uint32_t node_base, std::uint32_t leaf_base,
                      std::vector<shader::BvhNode>& out);

}  // namespace gi::bvh
