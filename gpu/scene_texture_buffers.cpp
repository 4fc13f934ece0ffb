#include "gpu/scene_texture_buffers.h"

#include <algorithm>

#include "gpu/compute_pass.h"
#include "gpu/device.h"

namespace gi::gpu {

SceneTextureBuffers::SceneTextureBuffers(Device& device) : device_(device) {
  upload(vertex_attributes_, nullptr, 0, "vertex attributes");
  upload(material_textures_, nullptr, 0, "material textures");
  upload(texture_images_, nullptr, 0, "texture images");
  upload(texels_, nullptr, 0, "texels");
}

bool SceneTextureBuffers::upload(Buffer& buffer, const void* data, std::size_t bytes, const char* name) {
  bool replaced = false;
  if (!buffer || buffer.size() < bytes) {
    buffer = Buffer(device_, std::max<VkDeviceSize>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, name);
    replaced = true;
  }
  if (bytes) buffer.upload_bytes(data, bytes);
  return replaced;
}

bool SceneTextureBuffers::update_geometry(const FlatGeometry& g) {
  bool replaced = upload(vertex_attributes_, g.vertex_attributes.data(),
                         g.vertex_attributes.size() * sizeof(GpuVertexAttributes), "vertex attributes");
  replaced |= upload(texture_images_, g.texture_images.data(), g.texture_images.size() * sizeof(GpuTextureImage),
                     "texture images");
  replaced |= upload(texels_, g.texels.data(), g.texels.size() * sizeof(std::uint32_t), "texels");
  return replaced;
}

bool SceneTextureBuffers::update_materials(const FlatInstances& flat) {
  return upload(material_textures_, flat.material_textures.data(),
                flat.material_textures.size() * sizeof(GpuMaterialTextures), "material textures");
}

void SceneTextureBuffers::add_to(SceneResources& scene) const {
  scene.vertex_attributes = &vertex_attributes_;
  scene.material_textures = &material_textures_;
  scene.texture_images = &texture_images_;
  scene.texels = &texels_;
}

}  // namespace gi::gpu
