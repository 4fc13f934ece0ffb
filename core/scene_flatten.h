// Turns a core::Scene into the flat arrays both renderers read
// (core/shared/scene_types.h). Geometry (vertices, indices) changes only when
// meshes are added; instances, materials and lights may change every frame.
#pragma once
#include <cstdint>
#include <vector>

#include "core/scene.h"
#include "core/shared/scene_types.h"

namespace gi {

using shader::FrameConstants;
using shader::GpuCamera;
using shader::GpuInstance;
using shader::GpuLight;
using shader::GpuMaterial;
using shader::GpuVertex;
using shader::GpuVertexAttributes;
using shader::GpuMaterialTextures;
using shader::GpuTextureImage;

static_assert(sizeof(GpuVertex) == 32);
static_assert(sizeof(GpuInstance) == 160);
static_assert(sizeof(GpuMaterial) == 48);
static_assert(sizeof(GpuLight) == 48);
static_assert(sizeof(GpuCamera) == 64);
static_assert(sizeof(FrameConstants) == 160);
static_assert(sizeof(GpuVertexAttributes) == 32);
static_assert(sizeof(GpuMaterialTextures) == 192);
static_assert(sizeof(GpuTextureImage) == 16);

struct MeshRange {
  std::uint32_t first_index = 0;
  std::uint32_t first_vertex = 0;
  std::uint32_t triangle_count = 0;
  std::uint32_t vertex_count = 0;
  bool operator==(const MeshRange&) const = default;
};

struct FlatGeometry {
  std::vector<GpuVertex> vertices;
  std::vector<std::uint32_t> indices;  // per mesh, relative to its first_vertex
  std::vector<MeshRange> meshes;
  // Textured scenes only (Scene::images not empty); else all three are empty
  // and the renderers bind placeholders.
  std::vector<GpuVertexAttributes> vertex_attributes;  // parallel to vertices
  std::vector<GpuTextureImage> texture_images;
  std::vector<std::uint32_t> texels;  // RGBA8, R in the low byte
};

struct FlatInstances {
  std::vector<GpuInstance> instances;  // one per Scene::instances entry, hidden ones included
  // Parallel to instances: last frame's object_to_world
  // (Instance::previous_transform, else this frame's), for the G-buffer's
  // motion vectors only.
  std::vector<glm::mat4> previous_object_to_world;
  std::vector<GpuMaterial> materials;
  std::vector<GpuMaterialTextures> material_textures;  // parallel to materials; empty without images
  std::vector<GpuLight> lights;        // directional lights first
  std::uint32_t directional_light_count = 0;
};

// Triangles of every mesh are reordered along a Morton curve of their
// centroids: lavapipe builds its BLAS by splitting the index list in order,
// and unsorted triangles made rays 500-1000x slower (docs/design.md §4). Both
// renderers see the same order, so primitive ids agree.
FlatGeometry flatten_geometry(const Scene& scene);

FlatInstances flatten_instances(const Scene& scene, const FlatGeometry& geometry);

GpuCamera make_gpu_camera(const Camera& camera, std::uint32_t width, std::uint32_t height);

// The constants of frame `frame` at `spp` samples per pixel. Sample indices
// start at frame · spp: they depend on the frame only, so a replay from any
// frame draws the same numbers as the run it replays.
FrameConstants frame_constants(const GpuCamera& camera, const GpuCamera& previous_camera, const FlatInstances& flat,
                               std::uint32_t width, std::uint32_t height, std::uint32_t frame, std::uint32_t seed,
                               std::uint32_t spp);

}  // namespace gi
