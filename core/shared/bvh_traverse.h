// Two-level BVH traversal of the `bvh` backend (layout: bvh_types.h), the
// same source on the GPU (gpu/shaders/trace_bvh.glsl) and on the CPU (the
// twin in core/bvh/bvh_cpu_tracer.h, which tests run against Embree).
//
// Bridge-included like scene_access.h: the includer first defines
//   BvhNode bvh_node(uint i);   BvhTriangle bvh_triangle(uint i);
// then includes this file — at file scope in GLSL, inside a struct body in
// C++. Needs bvh_types.h and watertight.h included before. No include guard
// on purpose.
//
// Traversal is a stack loop over 4-wide nodes: one node fetch (64 bytes)
// tests four quantised boxes with vec4 arithmetic, leaf children are intersected at once, and the
// inner children hit are sorted near-first by a 5-exchange network: the
// nearest is visited next, the others pushed far-first. The ray enters each
// instance's object space through the instance's world-to-object matrix
// without renormalising the direction, so object-space t equals world t.

GI_FN bool bvh_intersect_triangles(uint first, uint count, WatertightRay wr, bool any_hit, INOUT(float) best_t,
                                   INOUT(uint) best_primitive, INOUT(vec2) best_bary) {
  bool found = false;
  for (uint i = first; i < first + count; ++i) {
    BvhTriangle tri = bvh_triangle(i);
    float t;
    vec2 b;
    if (watertight_triangle(wr, tri.p0, tri.p1, tri.p2, best_t, t, b)) {
      best_t = t;
      best_primitive = tri.primitive;
      best_bary = b;
      found = true;
      if (any_hit) return true;
    }
  }
  return found;
}

// The slab test of ray_box (watertight.h) on a node's four dequantised boxes
// at once, component for component the same arithmetic. hit[c]: child c is
// not empty and its box meets [0, tmax]; tnear[c]: its entry distance.
GI_FN bvec4 bvh_ray_box4(BvhNode n, vec3 origin, vec3 inv, float tmax, OUT(vec4) tnear) {
  float sx = bvh_grid_step(n.scale_bits, 0u);
  float sy = bvh_grid_step(n.scale_bits, 1u);
  float sz = bvh_grid_step(n.scale_bits, 2u);
  // q * step is exact: the add is the only rounding, as the builder assumed.
  GI_PRECISE vec4 lo_x = n.origin.x + bvh_unpack_bytes(n.q_lo.x) * sx;
  GI_PRECISE vec4 hi_x = n.origin.x + bvh_unpack_bytes(n.q_hi.x) * sx;
  GI_PRECISE vec4 lo_y = n.origin.y + bvh_unpack_bytes(n.q_lo.y) * sy;
  GI_PRECISE vec4 hi_y = n.origin.y + bvh_unpack_bytes(n.q_hi.y) * sy;
  GI_PRECISE vec4 lo_z = n.origin.z + bvh_unpack_bytes(n.q_lo.z) * sz;
  GI_PRECISE vec4 hi_z = n.origin.z + bvh_unpack_bytes(n.q_hi.z) * sz;
  vec4 x0 = (lo_x - origin.x) * inv.x;
  vec4 x1 = (hi_x - origin.x) * inv.x;
  vec4 y0 = (lo_y - origin.y) * inv.y;
  vec4 y1 = (hi_y - origin.y) * inv.y;
  vec4 z0 = (lo_z - origin.z) * inv.z;
  vec4 z1 = (hi_z - origin.z) * inv.z;
  vec4 near = max(max(min(x0, x1), min(y0, y1)), max(min(z0, z1), vec4(0.0f)));
  vec4 far = min(min(max(x0, x1), max(y0, y1)), max(z0, z1)) * 1.0000004f;
  tnear = near;
  bvec4 in_box = lessThanEqual(near, min(far, vec4(tmax)));
  bvec4 used = notEqual(n.child, uvec4(BVH_CHILD_EMPTY));
  return bvec4(in_box.x && used.x, in_box.y && used.y, in_box.z && used.z, in_box.w && used.w);
}

// Orders (ka, ca) before (kb, cb) by key; equal keys keep their order.
GI_FN void bvh_order_pair(INOUT(float) ka, INOUT(uint) ca, INOUT(float) kb, INOUT(uint) cb) {
  bool swap = kb < ka;
  float k = swap ? kb : ka;
  uint c = swap ? cb : ca;
  kb = swap ? ka : kb;
  cb = swap ? ca : cb;
  ka = k;
  ca = c;
}

// The inner children of `n` that were hit and still start before tmax,
// nearest first: returns the nearest (BVH_CHILD_EMPTY if none) and pushes the
// others onto the stack, farthest first.
#define BVH_NEXT_INNER_CHILD(n, hit, tnear, tmax, stack, sp, next)                                    \
  {                                                                                                   \
    bool v0 = hit.x && !bvh_is_leaf(n.child.x) && tnear.x <= tmax;                                    \
    bool v1 = hit.y && !bvh_is_leaf(n.child.y) && tnear.y <= tmax;                                    \
    bool v2 = hit.z && !bvh_is_leaf(n.child.z) && tnear.z <= tmax;                                    \
    bool v3 = hit.w && !bvh_is_leaf(n.child.w) && tnear.w <= tmax;                                    \
    float k0 = v0 ? tnear.x : BVH_NO_KEY;                                                             \
    float k1 = v1 ? tnear.y : BVH_NO_KEY;                                                             \
    float k2 = v2 ? tnear.z : BVH_NO_KEY;                                                             \
    float k3 = v3 ? tnear.w : BVH_NO_KEY;                                                             \
    uint c0 = v0 ? n.child.x : BVH_CHILD_EMPTY;                                                       \
    uint c1 = v1 ? n.child.y : BVH_CHILD_EMPTY;                                                       \
    uint c2 = v2 ? n.child.z : BVH_CHILD_EMPTY;                                                       \
    uint c3 = v3 ? n.child.w : BVH_CHILD_EMPTY;                                                       \
    bvh_order_pair(k0, c0, k1, c1);                                                                   \
    bvh_order_pair(k2, c2, k3, c3);                                                                   \
    bvh_order_pair(k0, c0, k2, c2);                                                                   \
    bvh_order_pair(k1, c1, k3, c3);                                                                   \
    bvh_order_pair(k1, c1, k2, c2);                                                                   \
    if (c3 != BVH_CHILD_EMPTY) {                                                                      \
      stack[sp] = c3;                                                                                 \
      sp += 1u;                                                                                       \
    }                                                                                                 \
    if (c2 != BVH_CHILD_EMPTY) {                                                                      \
      stack[sp] = c2;                                                                                 \
      sp += 1u;                                                                                       \
    }                                                                                                 \
    if (c1 != BVH_CHILD_EMPTY) {                                                                      \
      stack[sp] = c1;                                                                                 \
      sp += 1u;                                                                                       \
    }                                                                                                 \
    next = c0;                                                                                        \
  }

// One BLAS in object space; true if it found a hit closer than best_t (which
// it then lowers).
GI_FN bool bvh_traverse_blas(uint root, vec3 origin, vec3 dir, bool any_hit, INOUT(float) best_t,
                             INOUT(uint) best_primitive, INOUT(vec2) best_bary) {
  WatertightRay wr = watertight_ray(origin, dir);
  vec3 inv = safe_inverse_direction(dir);
  uint stack[BVH_BLAS_STACK_SIZE];
  uint sp = 0u;
  bool found = false;
  // The root is read before the loop: where every lane enters the same BLAS
  // (one instance under the TLAS root) lavapipe loads it once for all lanes.
  BvhNode n = bvh_node(root);
  for (;;) {
    vec4 tnear;
    bvec4 hit = bvh_ray_box4(n, origin, inv, best_t, tnear);
    for (uint c = 0u; c < 4u; ++c) {
      if (hit[c] && bvh_is_leaf(n.child[c])) {
        if (bvh_intersect_triangles(bvh_leaf_first(n.child[c]), bvh_leaf_count(n.child[c]), wr, any_hit, best_t,
                                    best_primitive, best_bary)) {
          found = true;
          if (any_hit) return true;
        }
      }
    }
    uint next;
    BVH_NEXT_INNER_CHILD(n, hit, tnear, best_t, stack, sp, next)
    if (next == BVH_CHILD_EMPTY) {
      if (sp == 0u) break;
      sp -= 1u;
      next = stack[sp];
    }
    n = bvh_node(next);
  }
  return found;
}

GI_FN bool bvh_intersect_instances(uint first, uint count, vec3 origin, vec3 dir, bool any_hit,
                                   INOUT(float) best_t, INOUT(uint) best_instance, INOUT(uint) best_primitive,
                                   INOUT(vec2) best_bary) {
  bool found = false;
  for (uint i = first; i < first + count; ++i) {
    BvhInstance r = bvh_instance_from_node(bvh_node(i));
    mat3 m = mat3(r.world_to_object_c0, r.world_to_object_c1, r.world_to_object_c2);
    vec3 o = m * origin + r.world_to_object_c3;
    vec3 d = m * dir;
    if (bvh_traverse_blas(r.blas_root, o, d, any_hit, best_t, best_primitive, best_bary)) {
      best_instance = r.instance;
      found = true;
      if (any_hit) return true;
    }
  }
  return found;
}

// The TLAS leaf children of `n` that the ray's box test hit; true if an
// any-hit trace is done.
GI_FN bool bvh_visit_instance_leaves(BvhNode n, bvec4 box_hit, vec3 origin, vec3 dir, bool any_hit,
                                     INOUT(float) best_t, INOUT(uint) best_instance, INOUT(uint) best_primitive,
                                     INOUT(vec2) best_bary, INOUT(bool) found) {
  for (uint c = 0u; c < 4u; ++c) {
    if (box_hit[c] && bvh_is_leaf(n.child[c])) {
      if (bvh_intersect_instances(bvh_leaf_first(n.child[c]), bvh_leaf_count(n.child[c]), origin, dir, any_hit,
                                  best_t, best_instance, best_primitive, best_bary)) {
        found = true;
        if (any_hit) return true;
      }
    }
  }
  return false;
}

// Closest hit (any_hit = false) or the first hit found (any_hit = true) with
// 0 < t < tmax, from the TLAS root (node 0).
GI_FN bool bvh_trace(vec3 origin, vec3 dir, float tmax, bool any_hit, OUT(Hit) hit) {
  vec3 inv = safe_inverse_direction(dir);
  uint stack[BVH_TLAS_STACK_SIZE];
  uint sp = 0u;
  float best_t = tmax;
  uint best_instance = 0u;
  uint best_primitive = 0u;
  vec2 best_bary = vec2(0.0f);
  bool found = false;
  // One visit loop from the root: a copy of the root's visit before the loop
  // (which let lavapipe load node 0 once for all lanes) put a second BLAS
  // traversal in every trace call, and the shader compiler inlines the whole
  // traversal at each call; the GI shaders' compile on lavapipe took twice as
  // long. Same nodes in the same order: the same bits.
  uint node = 0u;
  while (node != BVH_CHILD_EMPTY) {
    BvhNode n = bvh_node(node);
    vec4 tnear;
    bvec4 box_hit = bvh_ray_box4(n, origin, inv, best_t, tnear);
    if (bvh_visit_instance_leaves(n, box_hit, origin, dir, any_hit, best_t, best_instance, best_primitive,
                                  best_bary, found))
      break;
    uint next;
    BVH_NEXT_INNER_CHILD(n, box_hit, tnear, best_t, stack, sp, next)
    if (next == BVH_CHILD_EMPTY) {
      if (sp == 0u) break;
      sp -= 1u;
      next = stack[sp];
    }
    node = next;
  }
  hit.t = best_t;
  hit.instance = best_instance;
  hit.primitive = best_primitive;
  hit.barycentrics = best_bary;
  return found;
}
