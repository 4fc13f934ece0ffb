// The GLSL bridge to the shared scene code: binds the scene (TLAS, geometry,
// instances, materials, lights, frame constants), defines the accessors that
// core/shared/scene_access.h and path_integrator.h require, traces with ray
// queries, then includes both. A pass includes this file once, after #version
// and its extensions:
//   #include "gpu/shaders/scene_bindings.glsl"
// Define SCENE_BINDINGS_NO_INTEGRATOR before including it to leave out
// path_integrator.h (passes that trace no paths compile faster).
#extension GL_EXT_ray_query : require

#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"
#include "core/shared/scene_types.h"
#include "gpu/shaders/bindings.h"

layout(set = 0, binding = BINDING_TLAS) uniform accelerationStructureEXT scene_tlas;
layout(std430, set = 0, binding = BINDING_VERTICES) readonly buffer SceneVertices { GpuVertex scene_vertices[]; };
layout(std430, set = 0, binding = BINDING_INDICES) readonly buffer SceneIndices { uint scene_indices[]; };
layout(std430, set = 0, binding = BINDING_INSTANCES) readonly buffer SceneInstances { GpuInstance scene_instances[]; };
layout(std430, set = 0, binding = BINDING_MATERIALS) readonly buffer SceneMaterials { GpuMaterial scene_materials[]; };
layout(std430, set = 0, binding = BINDING_LIGHTS) readonly buffer SceneLights { GpuLight scene_lights[]; };
layout(std140, set = 0, binding = BINDING_FRAME) uniform Frame { FrameConstants frame; };

GpuInstance scene_instance(uint i) { return scene_instances[i]; }
GpuMaterial scene_material(uint i) { return scene_materials[i]; }
GpuVertex scene_vertex(uint i) { return scene_vertices[i]; }
uint scene_index(uint i) { return scene_indices[i]; }
GpuLight scene_light(uint i) { return scene_lights[i]; }
uint scene_light_count() { return frame.counts.x; }
uint scene_directional_light_count() { return frame.counts.y; }

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

#include "core/shared/scene_access.h"
#ifndef SCENE_BINDINGS_NO_INTEGRATOR
#include "core/shared/path_integrator.h"
#endif
