#include "core/bvh/bvh_builder.h"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "core/errors.h"

namespace gi::bvh {
namespace {

struct BuildNode {
  Aabb box;
  std::uint32_t first = 0, count = 0;  // leaf: range of `order`
  std::int32_t left = -1, right = -1;  // inner: build-node indices
};

class Builder {
 public:
  Builder(std::span<const Aabb> boxes, const BuildOptions& o) : boxes_(boxes), o_(o) {
    centroids_.reserve(boxes.size());
    for (const Aabb& b : boxes) centroids_.push_back(0.5f * (b.lo + b.hi));
    order_.resize(boxes.size());
    for (std::uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
  }

  BuiltBvh run() {
    BuiltBvh out;
    if (boxes_.empty()) {
      out.nodes.push_back(shader::BvhNode{});  // both children empty
      return out;
    }
    nodes_.push_back(BuildNode{});
    build(0, 0, std::uint32_t(order_.size()), 0);
    out.bounds = nodes_[0].box;
    out.depth = depth_;
    out.order = order_;
    emit(out);
    return out;
  }

 private:
  // Builds node `index` over order_[first, first + count).
  void build(std::size_t index, std::uint32_t first, std::uint32_t count, std::uint32_t depth) {
    Aabb box, cbox;
    for (std::uint32_t k = first; k < first + count; ++k) {
      box.grow(boxes_[order_[k]]);
      cbox.grow(centroids_[order_[k]]);
    }
    nodes_[index].box = box;
    nodes_[index].first = first;
    nodes_[index].count = count;
    if (count == 1) return;

    std::uint32_t mid = 0;
    const bool split = choose_split(box, cbox, first, count, mid);
    if (!split) return;  // leaf
    if (depth + 1 > o_.max_depth)
      throw DeviceError(fmt::format("BVH deeper than {} levels over {} primitives (traversal stack)", o_.max_depth,
                                    boxes_.size()));
    depth_ = std::max(depth_, depth + 1);
    const std::size_t left = nodes_.size();
    nodes_.push_back(BuildNode{});
    nodes_.push_back(BuildNode{});
    nodes_[index].left = std::int32_t(left);
    nodes_[index].right = std::int32_t(left + 1);
    nodes_[index].count = 0;
    build(left, first, mid - first, depth + 1);
    build(left + 1, mid, first + count - mid, depth + 1);
  }

  // Returns false for a leaf; else partitions order_[first, first+count) and
  // sets mid to the first index of the right half.
  bool choose_split(const Aabb& box, const Aabb& cbox, std::uint32_t first, std::uint32_t count,
                    std::uint32_t& mid) {
    const std::uint32_t bins = o_.bins;
    float best_cost = std::numeric_limits<float>::max();
    int best_axis = -1;
    std::uint32_t best_bin = 0;
    const glm::vec3 extent = cbox.hi - cbox.lo;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0f)) continue;
      std::vector<Aabb> bin_box(bins);
      std::vector<std::uint32_t> bin_count(bins, 0);
      for (std::uint32_t k = first; k < first + count; ++k) {
        const std::uint32_t b = bin_of(centroids_[order_[k]][axis], cbox.lo[axis], extent[axis]);
        bin_box[b].grow(boxes_[order_[k]]);
        ++bin_count[b];
      }
      // Sweep: right-to-left areas, then left-to-right costs.
      std::vector<float> right_area(bins, 0.0f);
      std::vector<std::uint32_t> right_count(bins, 0);
      Aabb acc;
      std::uint32_t n = 0;
      for (std::uint32_t b = bins - 1; b > 0; --b) {
        acc.grow(bin_box[b]);
        n += bin_count[b];
        right_area[b] = acc.half_area();
        right_count[b] = n;
      }
      Aabb left;
      std::uint32_t nl = 0;
      for (std::uint32_t b = 1; b < bins; ++b) {  // split between bin b-1 and b
        left.grow(bin_box[b - 1]);
        nl += bin_count[b - 1];
        if (nl == 0 || right_count[b] == 0) continue;
        const float cost = left.half_area() * float(nl) + right_area[b] * float(right_count[b]);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = b;
        }
      }
    }
    const float parent_area = box.half_area();
    const float leaf_cost = float(count);
    const float split_cost = o_.traversal_cost + (parent_area > 0.0f ? best_cost / parent_area : float(count));
    if (best_axis < 0) {
      // Centroids coincide (or no bin split separates them): a median split
      // keeps oversized leaves from forming.
      if (count <= o_.max_leaf_size) return false;
      mid = first + count / 2;
      return true;
    }
    if (count <= o_.max_leaf_size && leaf_cost <= split_cost) return false;
    const int axis = best_axis;
    const auto begin = order_.begin() + first, end = begin + count;
    const auto it = std::stable_partition(begin, end, [&](std::uint32_t p) {
      return bin_of(centroids_[p][axis], cbox.lo[axis], extent[axis]) < best_bin;
    });
    mid = std::uint32_t(it - order_.begin());
    return true;
  }

  std::uint32_t bin_of(float c, float lo, float extent) const {
    const float f = (c - lo) / extent * float(o_.bins);
    const std::uint32_t b = f <= 0.0f ? 0u : std::uint32_t(f);
    return std::min(b, o_.bins - 1);
  }

  // Emits inner build nodes depth-first (left subtree first) as two-box nodes.
  void emit(BuiltBvh& out) {
    const BuildNode& root = nodes_[0];
    if (root.left < 0) {  // the whole tree is one leaf
      shader::BvhNode n{};
      n.left_min = root.box.lo;
      n.left_max = root.box.hi;
      n.left_ref = root.first;
      n.left_count = root.count;
      out.nodes.push_back(n);
      return;
    }
    emit_inner(0, out);
  }

  std::uint32_t emit_inner(std::size_t index, BuiltBvh& out) {
    const std::uint32_t slot = std::uint32_t(out.nodes.size());
    out.nodes.push_back(shader::BvhNode{});
    const BuildNode& b = nodes_[index];
    const BuildNode& l = nodes_[b.left];
    const BuildNode& r = nodes_[b.right];
    const std::uint32_t left_ref = l.left < 0 ? l.first : emit_inner(b.left, out);
    const std::uint32_t right_ref = r.left < 0 ? r.first : emit_inner(b.right, out);
    shader::BvhNode& n = out.nodes[slot];
    n.left_min = l.box.lo;
    n.left_max = l.box.hi;
    n.left_ref = left_ref;
    n.left_count = l.left < 0 ? l.count : 0u;
    n.right_min = r.box.lo;
    n.right_max = r.box.hi;
    n.right_ref = right_ref;
    n.right_count = r.left < 0 ? r.count : 0u;
    return slot;
  }

  std::span<const Aabb> boxes_;
  BuildOptions o_;
  std::vector<glm::vec3> centroids_;
  std::vector<std::uint32_t> order_;
  std::vector<BuildNode> nodes_;
  std::uint32_t depth_ = 0;
};

}  // namespace

BuiltBvh build_bvh(std::span<const Aabb> boxes, const BuildOptions& options) {
  BuildOptions o = options;
  o.bins = std::max<std::uint32_t>(o.bins, 2);
  o.max_leaf_size = std::max<std::uint32_t>(o.max_leaf_size, 1);
  return Builder(boxes, o).run();
}

void append_relocated(const BuiltBvh& tree, std::uint32_t node_base, std::uint32_t leaf_base,
                      std::vector<shader::BvhNode>& out) {
  for (shader::BvhNode n : tree.nodes) {
    if (!shader::bvh_child_empty(n.left_ref, n.left_count)) n.left_ref += n.left_count > 0 ? leaf_base : node_base;
    if (!shader::bvh_child_empty(n.right_ref, n.right_count))
      n.right_ref += n.right_count > 0 ? leaf_base : node_base;
    out.push_back(n);
  }
}

}  // namespace gi::bvh
