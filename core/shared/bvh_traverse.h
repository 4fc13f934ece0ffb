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
// Traversal is a stack loop over the 4-wide nodes of both levels: one node
// fetch (64 bytes) tests four quantised boxes with vec4 arithmetic, leaf
// children are intersected at once, and the inner children hit are sorted near-first by a 5-exchange network: the
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

// The inner children in `child` that were hit and still start before tmax,
// nearest first: returns the nearest (BVH_CHILD_EMPTY if none) and pushes the
// others onto the stack, farthest first.
#define BVH_NEXT_INNER_CHILD(child, hit, tnear, tmax, stack, sp, next)                                \
  {                                                                                                   \
    bool v0 = hit.x && !bvh_is_leaf(child.x) && tnear.x <= tmax;                                      \
    bool v1 = hit.y && !bvh_is_leaf(child.y) && tnear.y <= tmax;                                      \
    bool v2 = hit.z && !bvh_is_leaf(child.z) && tnear.z <= tmax;                                      \
    bool v3 = hit.w && !bvh_is_leaf(child.w) && tnear.w <= tmax;                                      \
    float k0 = v0 ? tnear.x : BVH_NO_KEY;                                                             \
    float k1 = v1 ? tnear.y : BVH_NO_KEY;                                                             \
    float k2 = v2 ? tnear.z : BVH_NO_KEY;                                                             \
    float k3 = v3 ? tnear.w : BVH_NO_KEY;                                                             \
    uint c0 = v0 ? child.x : BVH_CHILD_EMPTY;                                                         \
    uint c1 = v1 ? child.y : BVH_CHILD_EMPTY;                                                         \
    uint c2 = v2 ? child.z : BVH_CHILD_EMPTY;                                                         \
    uint c3 = v3 ? child.w : BVH_CHILD_EMPTY;                                                         \
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

// Closest hit (any_hit = false) or the first hit found (any_hit = true) with
// 0 < t < tmax, from the TLAS root (node 0), in one of two forms that visit
// the same nodes in the same order with the same arithmetic (the same bits,
// tests/bvh_test.cpp): BVH_TRAVERSAL_ONE_LOOP (defined for CPU devices,
// gpu/bvh_buffers.cpp) or a loop per level.
#ifdef BVH_TRAVERSAL_ONE_LOOP
// Both levels are walked by one loop, with one box test and one child sort:
// the shader compiler inlines the whole traversal at every trace call, and a
// loop per level put two copies of each in every call (lavapipe compiles
// each copy with LLVM, which is most of a GI shader's compile). The BLAS
// stack sits on top of the TLAS stack in one array. While a TLAS node's
// instance leaves are walked, the node's children, box hits and entry
// distances wait in tlas_*, with a cursor (slot leaf_c next; instances
// [leaf_i, leaf_end) of the slot being walked). Nodes, instances and
// triangles are visited in the order a loop per level visits them (slots
// 0..3, instances in index order, the node's inner children after its
// instances, against the lowered best_t), with the same arithmetic: the
// same bits.
GI_FN bool bvh_trace(vec3 origin, vec3 dir, float tmax, bool any_hit, OUT(Hit) hit) {
  vec3 world_inv = safe_inverse_direction(dir);
  uint stack[BVH_TLAS_STACK_SIZE + BVH_BLAS_STACK_SIZE];
  uint sp = 0u;
  float best_t = tmax;
  uint best_instance = 0u;
  uint best_primitive = 0u;
  vec2 best_bary = vec2(0.0f);
  bool found = false;
  // The ray of the level being walked: world space in the TLAS, the
  // instance's object space (direction not renormalised) in a BLAS.
  vec3 ray_origin = origin;
  vec3 ray_inv = world_inv;
  WatertightRay wr;
  bool in_blas = false;
  uint blas_base = 0u;  // the stack depth below the BLAS being walked
  uint blas_instance = 0u;
  bool blas_found = false;
  uvec4 tlas_child = uvec4(BVH_CHILD_EMPTY);
  bvec4 tlas_hit = bvec4(false);
  vec4 tlas_near = vec4(0.0f);
  uint leaf_c = 4u;
  uint leaf_i = 0u;
  uint leaf_end = 0u;
  uint node = 0u;
  for (;;) {
    // node is BVH_CHILD_EMPTY on the step after a BLAS: the TLAS node waiting
    // in tlas_* goes on with its next instance.
    uvec4 child = tlas_child;
    bvec4 box_hit = tlas_hit;
    vec4 tnear = tlas_near;
    if (node != BVH_CHILD_EMPTY) {
      BvhNode n = bvh_node(node);
      child = n.child;
      box_hit = bvh_ray_box4(n, ray_origin, ray_inv, best_t, tnear);
      if (!in_blas) {
        tlas_child = child;
        tlas_hit = box_hit;
        tlas_near = tnear;
        leaf_c = 0u;
        leaf_i = 0u;
        leaf_end = 0u;
      }
    }
    if (in_blas) {
      for (uint c = 0u; c < 4u; ++c) {
        if (box_hit[c] && bvh_is_leaf(child[c])) {
          if (bvh_intersect_triangles(bvh_leaf_first(child[c]), bvh_leaf_count(child[c]), wr, any_hit, best_t,
                                      best_primitive, best_bary)) {
            blas_found = true;
            if (any_hit) break;
          }
        }
      }
      if (any_hit && blas_found) {
        best_instance = blas_instance;
        found = true;
        break;
      }
    } else {
      while (leaf_i == leaf_end && leaf_c < 4u) {
        if (tlas_hit[leaf_c] && bvh_is_leaf(tlas_child[leaf_c])) {
          leaf_i = bvh_leaf_first(tlas_child[leaf_c]);
          leaf_end = leaf_i + bvh_leaf_count(tlas_child[leaf_c]);
        }
        leaf_c += 1u;
      }
      if (leaf_i < leaf_end) {
        BvhInstance r = bvh_instance_from_node(bvh_node(leaf_i));
        leaf_i += 1u;
        mat3 m = mat3(r.world_to_object_c0, r.world_to_object_c1, r.world_to_object_c2);
        ray_origin = m * origin + r.world_to_object_c3;
        vec3 d = m * dir;
        ray_inv = safe_inverse_direction(d);
        wr = watertight_ray(ray_origin, d);
        in_blas = true;
        blas_base = sp;
        blas_instance = r.instance;
        blas_found = false;
        node = r.blas_root;
        continue;
      }
    }
    uint next;
    BVH_NEXT_INNER_CHILD(child, box_hit, tnear, best_t, stack, sp, next)
    if (next == BVH_CHILD_EMPTY) {
      if (sp == blas_base) {
        if (!in_blas) break;
        // The BLAS is done: back to its TLAS node's next instance.
        if (blas_found) {
          best_instance = blas_instance;
          found = true;
        }
        in_blas = false;
        blas_base = 0u;
        ray_origin = origin;
        ray_inv = world_inv;
        node = BVH_CHILD_EMPTY;
        continue;
      }
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
#else

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
    BVH_NEXT_INNER_CHILD(n.child, hit, tnear, best_t, stack, sp, next)
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

// A loop per level: on a GPU, where the shader compiler's time is no concern,
// the BLAS loop stays tight (the one loop made the H100's pipeline passes
// 6.5 % slower: reports/benchmarks/h100-unified-traversal-ab.json).
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
    BVH_NEXT_INNER_CHILD(n.child, box_hit, tnear, best_t, stack, sp, next)
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
#endif
