// The material-texture half of the scene on the GPU (core/shared/texture_sampling.h):
// vertex attributes (uv, tangent), each material's texture slots, the image
// table and the texels. Every pass binds them with the scene; an untextured
// scene gets 16-byte placeholders, which its shaders never read (a material
// reads them only when its reflectance.z says it is textured).
#pragma once
#include "core/scene_flatten.h"
#include "gpu/buffer.h"

namespace gi::gpu {

class Device;
struct SceneResources;

class SceneTextureBuffers {
 public:
  explicit SceneTextureBuffers(Device& device);

  // Geometry and images change together (flatten_geometry); the material
  // slots every frame with the materials. Each returns true when a buffer was
  // replaced, so the caller rebinds its passes.
  bool update_geometry(const FlatGeometry& geometry);
  bool update_materials(const FlatInstances& flat);

  void add_to(SceneResources& scene) const;
  VkDeviceSize texel_bytes() const { return texels_.size(); }

 private:
  bool upload(Buffer& buffer, const void* data, std::size_t bytes, const char* name);

  Device& device_;
  Buffer vertex_attributes_, material_textures_, texture_images_, texels_;
};

}  // namespace gi::gpu
