// The `bvh` backend of trace_closest/trace_unoccluded (docs/design.md §4): the
// CPU-built two-level BVH (core/bvh/scene_bvh.h, uploaded by
// gpu/bvh_buffers.*) traversed by core/shared/bvh_traverse.h with Woop's
// watertight triangle test. Plain Vulkan 1.2 compute: no GL_EXT_ray_query, so
// it runs on devices without ray query. Included by scene_bindings.glsl only.

#include "core/shared/bvh_types.h"
#include "core/shared/watertight.h"

layout(std430, set = 0, binding = BINDING_BVH_NODES) readonly buffer BvhNodes { BvhNode bvh_nodes[]; };
layout(std430, set = 0, binding = BINDING_BVH_TRIANGLES) readonly buffer BvhTriangles { BvhTriangle bvh_triangles[]; };

#ifdef TRACE_PREVIOUS_SCENE
// Last frame's node array; the traversal reads it while the flag is set.
layout(std430, set = 0, binding = BINDING_PREVIOUS_SCENE) readonly buffer PreviousBvhNodes { BvhNode previous_bvh_nodes[]; };
bool bvh_in_previous_scene = false;
BvhNode bvh_node(uint i) { return bvh_in_previous_scene ? previous_bvh_nodes[i] : bvh_nodes[i]; }
#else
BvhNode bvh_node(uint i) { return bvh_nodes[i]; }
#endif
BvhTriangle bvh_triangle(uint i) { return bvh_triangles[i]; }

#include "core/shared/bvh_traverse.h"

// tmin is 0: the shared code offsets ray origins itself (offset_ray_origin).
bool trace_closest(vec3 origin, vec3 dir, float tmax, out Hit hit) { return bvh_trace(origin, dir, tmax, false, hit); }

bool trace_unoccluded(vec3 origin, vec3 dir, float tmax) {
  Hit ignored;
  return !bvh_trace(origin, dir, tmax, true, ignored);
}

#ifdef TRACE_PREVIOUS_SCENE
// trace_unoccluded against last frame's scene.
bool trace_unoccluded_previous_scene(vec3 origin, vec3 dir, float tmax) {
  bvh_in_previous_scene = true;
  bool unoccluded = trace_unoccluded(origin, dir, tmax);
  bvh_in_previous_scene = false;
  return unoccluded;
}
#endif
