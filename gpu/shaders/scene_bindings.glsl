// The GLSL bridge to the shared scene code: binds the scene (geometry,
// instances, materials, lights, frame constants), defines the accessors that
// core/shared/scene_access.h and path_integrator.h require, defines the
// tracing interface trace_closest/trace_unoccluded, then includes both. A pass
// includes this file once, after #version and its extensions:
//   #include "gpu/shaders/scene_bindings.glsl"
// Define SCENE_BINDINGS_NO_INTEGRATOR before including it to leave out
// path_integrator.h (passes that trace no paths compile faster).
//
// The tracing backend is chosen at compile time (docs/design.md §4): the ShaderCompiler
// adds TRACE_BACKEND_BVH for the compute BVH (trace_bvh.glsl), else ray
// queries are used (trace_rayquery.glsl). Passes never know which one runs.
#ifndef TRACE_BACKEND_BVH
#extension GL_EXT_ray_query : require
#endif

#include "gpu/shaders/bindings.h"
layout(std430, set = 0, binding = BINDING_DFG_LUT) readonly buffer DfgLut { uint dfg_lut_words[]; };
#define GI_DFG_LUT_WORD(i) dfg_lut_words[i]
#include "core/shared/brdf.h"
#include "core/shared/rng.h"
#include "core/shared/sampling.h"
#include "core/shared/scene_types.h"
#include "gpu/shaders/bindings.h"

layout(std430, set = 0, binding = BINDING_VERTICES) readonly buffer SceneVertices { GpuVertex scene_vertices[]; };
layout(std430, set = 0, binding = BINDING_INDICES) readonly buffer SceneIndices { uint scene_indices[]; };
layout(std430, set = 0, binding = BINDING_INSTANCES) readonly buffer SceneInstances { GpuInstance scene_instances[]; };
layout(std430, set = 0, binding = BINDING_MATERIALS) readonly buffer SceneMaterials { GpuMaterial scene_materials[]; };
layout(std430, set = 0, binding = BINDING_LIGHTS) readonly buffer SceneLights { GpuLight scene_lights[]; };
layout(std140, set = 0, binding = BINDING_FRAME) uniform Frame { FrameConstants frame; };
layout(std430, set = 0, binding = BINDING_VERTEX_ATTRIBUTES) readonly buffer SceneVertexAttributes {
  GpuVertexAttributes scene_vertex_attribute_array[];
};
layout(std430, set = 0, binding = BINDING_MATERIAL_TEXTURES) readonly buffer SceneMaterialTextures {
  GpuMaterialTextures scene_material_texture_array[];
};
layout(std430, set = 0, binding = BINDING_TEXTURE_IMAGES) readonly buffer SceneTextureImages {
  GpuTextureImage scene_texture_image_array[];
};
layout(std430, set = 0, binding = BINDING_TEXELS) readonly buffer SceneTexels { uint scene_texel_array[]; };

GpuInstance scene_instance(uint i) { return scene_instances[i]; }
GpuMaterial scene_material(uint i) { return scene_materials[i]; }
GpuVertex scene_vertex(uint i) { return scene_vertices[i]; }
uint scene_index(uint i) { return scene_indices[i]; }
GpuLight scene_light(uint i) { return scene_lights[i]; }
uint scene_light_count() { return frame.counts.x; }
uint scene_directional_light_count() { return frame.counts.y; }
GpuVertexAttributes scene_vertex_attributes(uint i) { return scene_vertex_attribute_array[i]; }
GpuMaterialTextures scene_material_textures(uint i) { return scene_material_texture_array[i]; }
GpuTextureImage scene_texture_image(uint i) { return scene_texture_image_array[i]; }
uint scene_texel(uint i) { return scene_texel_array[i]; }

#ifdef TRACE_BACKEND_BVH
#include "gpu/shaders/trace_bvh.glsl"
#else
#include "gpu/shaders/trace_rayquery.glsl"
#endif

#include "core/shared/scene_access.h"
#ifndef SCENE_BINDINGS_NO_INTEGRATOR
#include "core/shared/path_integrator.h"
#endif
