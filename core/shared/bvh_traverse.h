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
// Traversal is a plain stack loop over two-box nodes: both children are
// tested from one node fetch, leaf children are intersected at once, inner
// children are visited near-first with the far one pushed. The ray enters
// each instance's object space through the instance's world-to-object matrix
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

// One BLAS in object space; true if it found a hit closer than best_t (which
// it then lowers).
GI_FN bool bvh_traverse_blas(uint root, vec3 origin, vec3 dir, bool any_hit, INOUT(float) best_t,
                             INOUT(uint) best_primitive, INOUT(vec2) best_bary) {
  WatertightRay wr = watertight_ray(origin, dir);
  vec3 inv = safe_inverse_direction(dir);
  uint stack[BVH_BLAS_STACK_SIZE];
  uint sp = 0u;
  uint node = root;
  bool found = false;
  for (;;) {
    BvhNode n = bvh_node(node);
    float tl = 0.0f;
    float tr = 0.0f;
    bool hl = !bvh_child_empty(n.left_ref, n.left_count) &&
              ray_box(n.left_min, n.left_max, origin, inv, best_t, tl);
    bool hr = !bvh_child_empty(n.right_ref, n.right_count) &&
              ray_box(n.right_min, n.right_max, origin, inv, best_t, tr);
    if (hl && n.left_count > 0u) {
      if (bvh_intersect_triangles(n.left_ref, n.left_count, wr, any_hit, best_t, best_primitive, best_bary)) {
        found = true;
        if (any_hit) return true;
      }
      hl = false;
    }
    if (hr && n.right_count > 0u) {
      if (bvh_intersect_triangles(n.right_ref, n.right_count, wr, any_hit, best_t, best_primitive, best_bary)) {
        found = true;
        if (any_hit) return true;
      }
      hr = false;
    }
    if (hl && hr) {
      bool left_first = tl <= tr;
      stack[sp] = left_first ? n.right_ref : n.left_ref;
      sp += 1u;
      node = left_first ? n.left_ref : n.right_ref;
    } else if (hl) {
      node = n.left_ref;
    } else if (hr) {
      node = n.right_ref;
    } else {
      if (sp == 0u) break;
      sp -= 1u;
      node = stack[sp];
    }
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

// Closest hit (any_hit = false) or the first hit found (any_hit = true) with
// 0 < t < tmax, from the TLAS root (node 0).
GI_FN bool bvh_trace(vec3 origin, vec3 dir, float tmax, bool any_hit, OUT(Hit) hit) {
  vec3 inv = safe_inverse_direction(dir);
  uint stack[BVH_TLAS_STACK_SIZE];
  uint sp = 0u;
  uint node = 0u;
  float best_t = tmax;
  uint best_instance = 0u;
  uint best_primitive = 0u;
  vec2 best_bary = vec2(0.0f);
  bool found = false;
  for (;;) {
    BvhNode n = bvh_node(node);
    float tl = 0.0f;
    float tr = 0.0f;
    bool hl = !bvh_child_empty(n.left_ref, n.left_count) &&
              ray_box(n.left_min, n.left_max, origin, inv, best_t, tl);
    bool hr = !bvh_child_empty(n.right_ref, n.right_count) &&
              ray_box(n.right_min, n.right_max, origin, inv, best_t, tr);
    if (hl && n.left_count > 0u) {
      if (bvh_intersect_instances(n.left_ref, n.left_count, origin, dir, any_hit, best_t, best_instance,
                                  best_primitive, best_bary)) {
        found = true;
        if (any_hit) break;
      }
      hl = false;
    }
    if (hr && n.right_count > 0u) {
      if (bvh_intersect_instances(n.right_ref, n.right_count, origin, dir, any_hit, best_t, best_instance,
                                  best_primitive, best_bary)) {
        found = true;
        if (any_hit) break;
      }
      hr = false;
    }
    if (hl && hr) {
      bool left_first = tl <= tr;
      stack[sp] = left_first ? n.right_ref : n.left_ref;
      sp += 1u;
      node = left_first ? n.left_ref : n.right_ref;
    } else if (hl) {
      node = n.left_ref;
    } else if (hr) {
      node = n.right_ref;
    } else {
      if (sp == 0u) break;
      sp -= 1u;
      node = stack[sp];
    }
  }
  hit.t = best_t;
  hit.instance = best_instance;
  hit.primitive = best_primitive;
  hit.barycentrics = best_bary;
  return found;
}
