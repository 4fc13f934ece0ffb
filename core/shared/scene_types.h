// The flattened scene as both renderers read it (std430 layout on the GPU;
// the same bytes on the CPU). core/scene_flatten.cpp builds it from core::Scene.
// Every struct is a whole number of vec4s so std430 and C++ agree; the C++ side
// static_asserts the sizes.
#ifndef GI_SHARED_SCENE_TYPES_H
#define GI_SHARED_SCENE_TYPES_H
#include "host_device.h"
#include "texture_sampling.h"

GI_SHADER_BEGIN

struct GpuVertex {
  vec4 position;  // xyz object space, w = 1
  vec4 normal;    // xyz object-space shading normal, w = 1 if present, 0 if the
                  // mesh has none (then the geometric normal is used)
};

struct GpuInstance {
  mat4 object_to_world;
  mat4 normal_to_world;  // inverse transpose of object_to_world
  uint first_index;      // into the global index buffer
  uint first_vertex;     // added to every index of this instance's mesh
  uint triangle_count;
  uint material;
  vec4 emissive_scale;   // rgb multiplies the material's emissive (light on/off,
                         // intensity, colour events); w unused
};

struct GpuMaterial {
  vec4 base_color_metallic;             // rgb base colour, a metallic
  vec4 emissive_perceptual_roughness;   // rgb emissive radiance, a perceptual roughness
  vec4 reflectance;                     // x reflectance (0.5 = 4% F0), y the material model
                                        // (brdf.h BRDF_*, Scene::brdf_model), z 1 if the
                                        // material has textures (GpuMaterialTextures), w unused
};

GI_CONST uint LIGHT_KIND_EMISSIVE_MESH = 0u;
GI_CONST uint LIGHT_KIND_DIRECTIONAL = 1u;

// One entry per enabled light. Lights are picked uniformly, then (for meshes)
// a triangle uniformly, then a point uniformly: inverse pdf =
// light_count * triangle_count * area, as in Solari's light tiles.
struct GpuLight {
  uint kind;
  uint instance;        // emissive mesh: the instance; directional: unused
  uint triangle_count;  // emissive mesh: triangles of the instance's mesh
  uint pad0;
  vec4 direction;       // directional: unit vector towards the light, w = 1 - cos(angular radius)
  vec4 radiance;        // directional: rgb radiance inside the cone
};

// A pinhole camera. right/up are pre-scaled by tan(vfov/2) (and aspect), so a
// pixel's ray is forward + ndc.x * right + ndc.y * up.
struct GpuCamera {
  vec4 position;
  vec4 forward;
  vec4 right;
  vec4 up;
};

// Swizzles differ between GLSL (.xyz) and GLM, so shared code converts with
// vec3(v4), which both languages accept.

// Per-frame constants for every pass.
struct FrameConstants {
  GpuCamera camera;
  GpuCamera previous_camera;
  uvec4 resolution_frame;  // x, y resolution, z frame index, w seed
  uvec4 counts;            // x light count, y directional light count (the first y
                           // lights), z samples per pixel this frame, w sample base
};

// A ray hit as both tracers report it: barycentrics (u, v) weight vertices 1 and
// 2 of the triangle (Vulkan and Embree share this convention).
struct Hit {
  float t;
  uint instance;
  uint primitive;
  vec2 barycentrics;
};

// What a renderer needs to know about a surface point.
struct SurfacePoint {
  vec3 position;
  vec3 geometric_normal;  // unit, from the winding (counter-clockwise = front)
  vec3 shading_normal;    // unit, interpolated vertex normal or geometric
  // The interpolated vertex normal before any normal map (geometric where the
  // mesh has none), never flipped: what Bevy calls a hit's
  // geometric_world_normal (v0.18.0 scene/raytracing_scene_bindings.wgsl:199-201)
  // and keys the world cache with (world_cache.hit_normal "vertex").
  vec3 vertex_normal;
  float area;             // world-space area of the triangle
  vec3 emissive;          // radiance emitted from the front face
  uint material;
  // The material at this point: its factors times its textures there.
  vec4 base_color_metallic;  // rgb base colour, a metallic
  float perceptual_roughness;
  // The mesh's tangent where a normal map bent shading_normal: world space,
  // normalised, not made perpendicular to shading_normal; w the bitangent's
  // sign. w = 0: none (Solari 0.18 built its glossy-path frame from it, #23948).
  vec4 mesh_tangent;
};

GI_CONST float RAY_TMAX = 1e20f;

GI_FN vec3 camera_ray_direction(GpuCamera c, uvec2 pixel, uvec2 resolution) {
  vec2 ndc = (vec2(pixel) + vec2(0.5f)) / vec2(resolution) * 2.0f - vec2(1.0f);
  return normalize(vec3(c.forward) + ndc.x * vec3(c.right) - ndc.y * vec3(c.up));
}

GI_SHADER_END

#endif
