// The `bvh` tracing backend's GPU layout (DESIGN §4), shared by the CPU
// builder (core/bvh/), the CPU twin of the traversal (core/shared/bvh_traverse.h
// run from C++) and the compute shaders (gpu/shaders/trace_bvh.glsl).
//
// Two levels, like the `rayquery` backend: one BLAS per mesh over its
// object-space triangles, built once, and a small TLAS over the visible
// instances, rebuilt on the CPU when a transform or the visible set changes.
// All nodes live in one array: [TLAS nodes | instance records | BLAS nodes].
//
// Every struct is four (vec3, uint) pairs or three: std430 packs a vec3 and the
// uint after it into 16 bytes, exactly as C++ lays out glm::vec3 + uint32, so
// both sides read the same bytes without bit casts.
#ifndef GI_SHARED_BVH_TYPES_H
#define GI_SHARED_BVH_TYPES_H
#include "host_device.h"

GI_SHADER_BEGIN

// A binary node that stores both children's boxes, so one fetch tests both.
// A child with count == 0 is an inner node (ref = its node index); count > 0
// is a leaf of `count` consecutive entries starting at ref (triangles in a
// BLAS, instance records in the TLAS). ref == 0 with count == 0 is an empty
// child (node 0 is the TLAS root, never anyone's child); it occurs only in a
// root whose whole tree is one leaf, or in an empty TLAS.
struct BvhNode {
  vec3 left_min;
  uint left_ref;
  vec3 left_max;
  uint left_count;
  vec3 right_min;
  uint right_ref;
  vec3 right_max;
  uint right_count;
};

// A TLAS leaf entry, stored in the node array with BvhNode's layout (read
// through bvh_instance_from_node): the world-to-object 3x4 matrix as four
// columns, the BLAS root, the instance's index in FlatInstances, and pad.
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

// Deepest traversal stacks (the builder refuses trees deeper than these).
GI_CONST uint BVH_BLAS_STACK_SIZE = 48u;
GI_CONST uint BVH_TLAS_STACK_SIZE = 24u;
GI_FN bool bvh_child_empty(uint ref, uint count) { return ref == 0u && count == 0u; }

GI_FN BvhInstance bvh_instance_from_node(BvhNode n) {
  BvhInstance i;
  i.world_to_object_c0 = n.left_min;
  i.blas_root = n.left_ref;
  i.world_to_object_c1 = n.left_max;
  i.instance = n.left_count;
  i.world_to_object_c2 = n.right_min;
  i.pad0 = n.right_ref;
  i.world_to_object_c3 = n.right_max;
  i.pad1 = n.right_count;
  return i;
}

GI_FN BvhNode bvh_node_from_instance(BvhInstance i) {
  BvhNode n;
  n.left_min = i.world_to_object_c0;
  n.left_ref = i.blas_root;
  n.left_max = i.world_to_object_c1;
  n.left_count = i.instance;
  n.right_min = i.world_to_object_c2;
  n.right_ref = i.pad0;
  n.right_max = i.world_to_object_c3;
  n.right_count = i.pad1;
  return n;
}

GI_SHADER_END

#endif
