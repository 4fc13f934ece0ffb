#include "core/bvh/bvh_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "core/errors.h"

namespace gi::bvh {
namespace {

// Recursion guard of the binary build (the traversal stack is checked on the
// collapsed tree).
constexpr std::uint32_t kMaxBinaryDepth = 128;

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
      out.nodes.push_back(empty_node());  // every child empty
      return out;
    }
    nodes_.push_back(BuildNode{});
    build(0, 0, std::uint32_t(order_.size()), 0);
    out.bounds = nodes_[0].box;
    out.depth = depth_;
    out.order = order_;
    emit(out);
    if (out.stack_need > o_.stack_size)
      throw DeviceError(fmt::format("BVH over {} primitives needs {} traversal stack entries, more than {}",
                                    boxes_.size(), out.stack_need, o_.stack_size));
    if (order_.size() > shader::BVH_LEAF_FIRST_MASK)
      throw DeviceError(fmt::format("BVH over {} primitives: more than a leaf reference holds", boxes_.size()));
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
    if (depth + 1 > kMaxBinaryDepth)
      throw DeviceError(fmt::format("BVH deeper than {} levels over {} primitives", kMaxBinaryDepth, boxes_.size()));
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

  // Emits the binary tree collapsed to 4-wide nodes, depth-first. A node's
  // children start as the binary node's two; while fewer than four, the inner
  // child with the largest surface area (the first on ties) is replaced by its
  // own two children, in place, so child order stays left-to-right.
  void emit(BuiltBvh& out) {
    const BuildNode& root = nodes_[0];
    if (root.left < 0) {  // the whole tree is one leaf
      shader::BvhNode n = empty_node();
      set_boxes(n, &root.box, 1);
      n.child[0] = shader::bvh_make_leaf(root.first, root.count);
      out.nodes.push_back(n);
      return;
    }
    out.stack_need = emit_inner(0, out);
  }

  static shader::BvhNode empty_node() {
    shader::BvhNode n{};
    n.child = glm::uvec4(shader::BVH_CHILD_EMPTY);
    return n;
  }

  // Quantises the boxes of n's children (boxes[c] for c < count) on a grid
  // of their union (see bvh_types.h): origin its low corner, per axis the
  // smallest power-of-two step that spans the extent in 252 steps, each lo
  // plane rounded down and hi plane up, checked with the float arithmetic
  // the traversal dequantises with.
  static void set_boxes(shader::BvhNode& n, const Aabb* boxes, std::size_t count) {
    Aabb all;
    for (std::size_t c = 0; c < count; ++c) all.grow(boxes[c]);
    n.origin = all.lo;
    n.scale_bits = 0;
    for (int k = 0; k < 3; ++k) {
      const double extent = double(all.hi[k]) - double(all.lo[k]);
      int e = -100;  // steps stay normal floats: q * step is exact and never flushed
      while (e < 127 && std::ldexp(252.0, e) < extent) ++e;
      const std::uint32_t biased = std::uint32_t(e + 127);
      n.scale_bits |= biased << (8 * k);
      const float step = shader::bvh_grid_step(n.scale_bits, std::uint32_t(k));
      const auto value = [&](std::uint32_t q) { return n.origin[k] + float(q) * step; };
      std::uint32_t lo_bytes = 0, hi_bytes = 0;
      for (std::size_t c = 0; c < count; ++c) {
        const double lo_rel = (double(boxes[c].lo[k]) - double(n.origin[k])) / double(step);
        const double hi_rel = (double(boxes[c].hi[k]) - double(n.origin[k])) / double(step);
        std::uint32_t qlo = std::uint32_t(std::clamp(std::floor(lo_rel), 0.0, 255.0));
        std::uint32_t qhi = std::uint32_t(std::clamp(std::ceil(hi_rel), 0.0, 255.0));
        while (qlo > 0 && value(qlo) > boxes[c].lo[k]) --qlo;
        while (qhi < 255 && value(qhi) < boxes[c].hi[k]) ++qhi;
        if (value(qlo) > boxes[c].lo[k] || value(qhi) < boxes[c].hi[k])
          throw DeviceError(fmt::format("BVH box quantisation failed on axis {} ({} .. {})", k, boxes[c].lo[k],
                                        boxes[c].hi[k]));
        lo_bytes |= qlo << (8 * c);
        hi_bytes |= qhi << (8 * c);
      }
      n.q_lo[k] = lo_bytes;
      n.q_hi[k] = hi_bytes;
    }
  }

  // Returns the stack entries traversing this subtree can need: a node pushes
  // all but one of its inner children, then descends into any of them.
  std::uint32_t emit_inner(std::size_t index, BuiltBvh& out) {
    const std::uint32_t slot = std::uint32_t(out.nodes.size());
    out.nodes.push_back(empty_node());
    std::vector<std::size_t> kids = {std::size_t(nodes_[index].left), std::size_t(nodes_[index].right)};
    while (kids.size() < 4) {
      int open = -1;
      float area = -1.0f;
      for (std::size_t k = 0; k < kids.size(); ++k) {
        const BuildNode& b = nodes_[kids[k]];
        if (b.left >= 0 && b.box.half_area() > area) {
          area = b.box.half_area();
          open = int(k);
        }
      }
      if (open < 0) break;
      const BuildNode& b = nodes_[kids[open]];
      const std::size_t l = std::size_t(b.left), r = std::size_t(b.right);
      kids[open] = l;
      kids.insert(kids.begin() + open + 1, r);
    }
    shader::BvhNode n = empty_node();
    Aabb boxes[4];
    for (std::size_t k = 0; k < kids.size(); ++k) boxes[k] = nodes_[kids[k]].box;
    set_boxes(n, boxes, kids.size());
    std::uint32_t inner = 0, deepest = 0;
    for (std::size_t k = 0; k < kids.size(); ++k) {
      const BuildNode& b = nodes_[kids[k]];
      if (b.left < 0) n.child[int(k)] = shader::bvh_make_leaf(b.first, b.count);
      if (b.left >= 0) {
        ++inner;
        n.child[int(k)] = std::uint32_t(out.nodes.size());
        deepest = std::max(deepest, emit_inner(kids[k], out));
      }
    }
    out.nodes[slot] = n;
    return (inner > 0 ? inner - 1 : 0) + deepest;
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
  o.max_leaf_size = std::clamp<std::uint32_t>(o.max_leaf_size, 1, shader::BVH_MAX_LEAF_SIZE);
  return Builder(boxes, o).run();
}

void append_relocated(const BuiltBvh& tree, std::uint32_t node_base, std::uint32_t leaf_base,
                      std::vector<shader::BvhNode>& out) {
  for (shader::BvhNode n : tree.nodes) {
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t ch = n.child[c];
      if (ch == shader::BVH_CHILD_EMPTY) continue;
      if (!shader::bvh_is_leaf(ch)) {
        n.child[c] = ch + node_base;
        continue;
      }
      const std::uint64_t first = std::uint64_t(shader::bvh_leaf_first(ch)) + leaf_base;
      if (first >= shader::BVH_LEAF_FIRST_MASK)
        throw DeviceError(fmt::format("BVH leaf reference {} out of range (at most {} entries)", first,
                                      shader::BVH_LEAF_FIRST_MASK));
      n.child[c] = shader::bvh_make_leaf(std::uint32_t(first), shader::bvh_leaf_count(ch));
    }
    out.push_back(n);
  }
}

}  // namespace gi::bvh
