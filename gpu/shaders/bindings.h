// Descriptor binding numbers and workgroup sizes, defined once for C++ and
// GLSL (host_device.h rules). Every pass uses descriptor set 0: the scene
// bindings (0-6 and the DFG table's 14, declared by scene_bindings.glsl)
// plus its own from 8 up.
// Binding numbers are unique across passes, so a buffer shared by two passes
// (the visibility buffer) has one number everywhere.
#ifndef GI_GPU_SHADERS_BINDINGS_H
#define GI_GPU_SHADERS_BINDINGS_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

// Scene (scene_bindings.glsl).
GI_CONST uint BINDING_TLAS = 0u;              // accelerationStructureEXT
GI_CONST uint BINDING_VERTICES = 1u;          // GpuVertex[]
GI_CONST uint BINDING_INDICES = 2u;           // uint[], per mesh, relative to first_vertex
GI_CONST uint BINDING_INSTANCES = 3u;         // GpuInstance[]
GI_CONST uint BINDING_MATERIALS = 4u;         // GpuMaterial[]
GI_CONST uint BINDING_LIGHTS = 5u;            // GpuLight[]
GI_CONST uint BINDING_FRAME = 6u;             // uniform FrameConstants
GI_CONST uint SCENE_BINDING_COUNT = 7u;
// Material textures (core/shared/texture_sampling.h), bound with the scene for
// every pass; 16-byte placeholders in a scene without textures, which never
// reads them.
GI_CONST uint BINDING_VERTEX_ATTRIBUTES = 16u;   // GpuVertexAttributes[], parallel to the vertices
GI_CONST uint BINDING_MATERIAL_TEXTURES = 17u;   // GpuMaterialTextures[], parallel to the materials
GI_CONST uint BINDING_TEXTURE_IMAGES = 18u;      // GpuTextureImage[]
GI_CONST uint BINDING_TEXELS = 19u;              // uint[] RGBA8
// BRDF_LAYERED's DFG table (core/shared/dfg_lut.h): bound with the scene for
// every pass; a buffer, as a constant array indexed per invocation is copied
// per invocation on lavapipe (minutes per frame).
GI_CONST uint BINDING_DFG_LUT = 14u;          // uint[] packHalf2x16(A, B)
// The `bvh` backend (TRACE_BACKEND_BVH) replaces the TLAS with two buffers;
// ComputePass swaps them in for BINDING_TLAS on a bvh Device.
GI_CONST uint BINDING_BVH_NODES = 0u;         // BvhNode[] (core/shared/bvh_types.h), in place of the TLAS
GI_CONST uint BINDING_BVH_TRIANGLES = 7u;     // BvhTriangle[]
// Last frame's scene, for DI's temporal MIS visibility only
// (TRACE_PREVIOUS_SCENE; restir_di.temporal_mis_scene previous_frame, Bevy
// #25046): its TLAS, or on the bvh backend its BVH node array (the triangles
// are shared: scenario events only append meshes).
GI_CONST uint BINDING_PREVIOUS_SCENE = 15u;

// Primary visibility / G-buffer.
GI_CONST uint BINDING_VISIBILITY = 8u;        // uvec2[] per pixel: instance, primitive (VISIBILITY_MISS)
GI_CONST uint BINDING_DEPTH = 9u;             // float[] per pixel: hit t (0 on a miss)
GI_CONST uint BINDING_GBUFFER = 10u;          // GBufferTexel[] per pixel
GI_CONST uint BINDING_PREVIOUS_TRANSFORMS = 20u;  // mat4[] per instance: last frame's object_to_world (motion vectors)

// Reference path tracer.
GI_CONST uint BINDING_REFERENCE_A = 11u;      // vec4[] per pixel: rgb sum, w samples (even sample indices)
GI_CONST uint BINDING_REFERENCE_B = 12u;      // vec4[] per pixel: the same for odd sample indices
GI_CONST uint BINDING_REFERENCE_NONFINITE = 13u;  // uint[1]: samples dropped for inf/NaN

// Ray passes run 8x8 = 64 invocations per workgroup (fastest on lavapipe, docs/design.md §4).
GI_CONST uint RAY_WORKGROUP_X = 8u;
GI_CONST uint RAY_WORKGROUP_Y = 8u;

GI_CONST uint VISIBILITY_MISS = 0xFFFFFFFFu;

GI_SHADER_END

#endif
