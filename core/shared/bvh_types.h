// The `bvh` tracing backend's GPU layout (docs/design.md §4), shared by the CPU
// builder (core/bvh/), the CPU twin of the traversal (core/shared/bvh_traverse.h
// run from C++) and the compute shaders (gpu/shaders/trace_bvh.glsl).
//
// Two levels, like the `rayquery` backend: one BLAS per mesh over its
// object-space triangles, built once, and a small TLAS over the visible
// instances, rebuilt on the CPU when a transform or the visible set changes.
// All nodes live in one array: [TLAS nodes | instance records | BLAS nodes].
//
// Every struct is vec4s, or (vec3, uint) pairs: std430 packs a vec3 and the
// uint after it into 16 bytes, exactly as C++ lays out glm::vec3 + uint32, so
// both sides read the same bytes without bit casts.
#ifndef GI_SHARED_BVH_TYPES_H
#define GI_SHARED_BVH_TYPES_H
#include "host_device.h"

GI_SHADER_BEGIN

// A 4-wide node (collapsed from the binary SAH tree, core/bvh/bvh_builder.cpp),
// 64 bytes: its four children's boxes quantised to 8 bits per plane on a grid
// of the node's own box. Plane k of child c is origin[k] + q * 2^(e[k] - 127)
// with q the byte c of q_lo[k] / q_hi[k] and e[k] the byte k of scale_bits;
// q * 2^(e - 127) is exact, so the one rounding is the add, and the builder
// picks each q so that the result still contains the child's float box (lo
// rounded down, hi up). The ray then meets the boxes with ray_box's slab test:
// conservative boxes only cost extra visits, never a missed hit.
//
// Why quantised: lavapipe reads a storage buffer at a per-lane address with
// one gather per 32-bit component, and a ray fetches ~11 nodes but tests
// only ~2 triangles (70k-triangle cliff, diffuse rays), so node bytes set
// the ray rate: 15 gathers a node here, 28 with float boxes, which were no
// faster as 4-wide nodes than the binary two-box nodes before them.
//
// child[c]: BVH_CHILD_EMPTY for an unused slot, a leaf (BVH_LEAF_BIT |
// (count - 1) << BVH_LEAF_COUNT_SHIFT | first: `count` consecutive entries
// from `first`, triangles in a BLAS, instance records in the TLAS), or else
// an inner node's index. Empty slots come last (their boxes are never read).
struct BvhNode {
  vec3 origin;
  uint scale_bits;  // bytes 0..2: biased exponents of the x, y, z grid steps
  uvec4 q_lo;       // x, y, z: lo planes of children 0..3, one byte each; w unused
  uvec4 q_hi;       // x, y, z: hi planes; w unused
  uvec4 child;
};

GI_CONST uint BVH_CHILD_EMPTY = 0xffffffffu;
GI_CONST uint BVH_LEAF_BIT = 0x80000000u;
GI_CONST uint BVH_LEAF_COUNT_SHIFT = 28u;          // bits 28..30: count - 1 (1..8 entries)
GI_CONST uint BVH_LEAF_FIRST_MASK = 0x0fffffffu;   // bits 0..27: first entry (< 2^28 - 1)
GI_CONST uint BVH_MAX_LEAF_SIZE = 8u;
// The traversal's sort key of a child not to visit (sorts last; ties keep order).
GI_CONST float BVH_NO_KEY = 3.402823466e38f;

GI_FN uint bvh_make_leaf(uint first, uint count) {
  return BVH_LEAF_BIT | ((count - 1u) << BVH_LEAF_COUNT_SHIFT) | first;
}
// A non-empty child is a leaf (BVH_CHILD_EMPTY also has the bit: test it first).
GI_FN bool bvh_is_leaf(uint child) { return (child & BVH_LEAF_BIT) != 0u; }
GI_FN uint bvh_leaf_first(uint child) { return child & BVH_LEAF_FIRST_MASK; }
GI_FN uint bvh_leaf_count(uint child) { return ((child >> BVH_LEAF_COUNT_SHIFT) & 7u) + 1u; }

// A TLAS leaf entry, stored in the node array in BvhNode's place (read
// through bvh_instance_from_node, bit for bit): the world-to-object 3x4
// matrix as four columns (origin, q_lo.xyz, q_hi.xyz, child.xyz as float
// bits), the BLAS root (scale_bits) and the instance's index in
// FlatInstances (q_lo.w).
struct BvhInstance {
  vec3 world_to_object_c0;
  uint blas_root;
  vec3 world_to_object_c1;
  uint instance;
  vec3 world_to_object_c2;
  uint pad0;
  vec3 world_to_object_c3;  // translation
  uint pad1;
};

// A triangle in BLAS leaf order: object-space corners and its index in the
// mesh (what ray queries report as the primitive index).
struct BvhTriangle {
  vec3 p0;
  uint primitive;
  vec3 p1;
  uint pad0;
  vec3 p2;
  uint pad1;
};

// Traversal stack sizes (entries). A 4-wide node pushes up to three inner
// children; the builder computes each tree's exact worst case and refuses
// trees that would need more.
GI_CONST uint BVH_BLAS_STACK_SIZE = 48u;
GI_CONST uint BVH_TLAS_STACK_SIZE = 32u;

GI_FN BvhInstance bvh_instance_from_node(BvhNode n) {
  BvhInstance i;
  i.world_to_object_c0 = n.origin;
  i.blas_root = n.scale_bits;
  i.world_to_object_c1 = uintBitsToFloat(uvec3(n.q_lo));
  i.instance = n.q_lo.w;
  i.world_to_object_c2 = uintBitsToFloat(uvec3(n.q_hi));
  i.pad0 = 0u;
  i.world_to_object_c3 = uintBitsToFloat(uvec3(n.child));
  i.pad1 = 0u;
  return i;
}

GI_FN BvhNode bvh_node_from_instance(BvhInstance i) {
  BvhNode n;
  n.origin = i.world_to_object_c0;
  n.scale_bits = i.blas_root;
  n.q_lo = uvec4(floatBitsToUint(i.world_to_object_c1), i.instance);
  n.q_hi = uvec4(floatBitsToUint(i.world_to_object_c2), 0u);
  n.child = uvec4(floatBitsToUint(i.world_to_object_c3), 0u);
  return n;
}

// The grid step 2^(e - 127) of axis k (0..2) of a node.
GI_FN float bvh_grid_step(uint scale_bits, uint k) { return uintBitsToFloat(((scale_bits >> (8u * k)) & 0xffu) << 23u); }
// Through ivec4: a signed conversion is one instruction on lavapipe's SIMD
// lanes, an unsigned one is not (both exact for bytes).
GI_FN vec4 bvh_unpack_bytes(uint w) { return vec4(ivec4((uvec4(w) >> uvec4(0u, 8u, 16u, 24u)) & uvec4(0xffu))); }

GI_SHADER_END

#endif
