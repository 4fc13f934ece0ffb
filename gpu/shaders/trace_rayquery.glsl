// The `rayquery` backend of trace_closest/trace_unoccluded (docs/design.md §4):
// GL_EXT_ray_query over the scene TLAS (gpu/acceleration_structures.*).
// Included by scene_bindings.glsl only; passes never include it themselves.

layout(set = 0, binding = BINDING_TLAS) uniform accelerationStructureEXT scene_tlas;

// tmin is 0: the shared code offsets ray origins itself (offset_ray_origin).
bool trace_closest(vec3 origin, vec3 dir, float tmax, out Hit hit) {
  rayQueryEXT q;
  rayQueryInitializeEXT(q, scene_tlas, gl_RayFlagsOpaqueEXT, 0xFFu, origin, 0.0, dir, tmax);
  while (rayQueryProceedEXT(q)) {
  }
  if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionNoneEXT) return false;
  hit.t = rayQueryGetIntersectionTEXT(q, true);
  hit.instance = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, true));
  hit.primitive = uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true));
  hit.barycentrics = rayQueryGetIntersectionBarycentricsEXT(q, true);
  return true;
}

bool trace_unoccluded(vec3 origin, vec3 dir, float tmax) {
  rayQueryEXT q;
  rayQueryInitializeEXT(q, scene_tlas, gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT, 0xFFu, origin, 0.0,
                        dir, tmax);
  while (rayQueryProceedEXT(q)) {
  }
  return rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionNoneEXT;
}

#ifdef TRACE_PREVIOUS_SCENE
layout(set = 0, binding = BINDING_PREVIOUS_SCENE) uniform accelerationStructureEXT previous_scene_tlas;

// trace_unoccluded against last frame's scene.
bool trace_unoccluded_previous_scene(vec3 origin, vec3 dir, float tmax) {
  rayQueryEXT q;
  rayQueryInitializeEXT(q, previous_scene_tlas, gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT, 0xFFu,
                        origin, 0.0, dir, tmax);
  while (rayQueryProceedEXT(q)) {
  }
  return rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionNoneEXT;
}
#endif
