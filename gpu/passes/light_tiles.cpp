#include "gpu/passes/light_tiles.h"

#include "gpu/buffer.h"
#include "gpu/shaders/di_bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

ComputePass make_pass(Device& device, ShaderCompiler& compiler, const DiSettings& s) {
  std::vector<DescriptorBinding> bindings = scene_descriptor_bindings();
  bindings.push_back({BINDING_LIGHT_TILE_SAMPLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_LIGHT_TILE_PACKED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return ComputePass(device, "light_tiles", compiler.compile_file(LightTiles::kShader, s.defines()).spirv,
                     std::move(bindings));
}

}  // namespace

LightTiles::LightTiles(Device& device, ShaderCompiler& compiler, const DiSettings& settings)
    : settings_(settings), pass_(make_pass(device, compiler, settings)) {}

void LightTiles::bind(const SceneResources& scene, const DiBuffers& b) {
  pass_.bind_scene(scene);
  pass_.bind_buffer(BINDING_LIGHT_TILE_SAMPLES, *b.tile_samples);
  pass_.bind_buffer(BINDING_LIGHT_TILE_PACKED, *b.tile_packed);
}

void LightTiles::record(VkCommandBuffer cmd) const {
  pass_.dispatch(cmd, group_count(settings_.tile_count * settings_.samples_per_tile, LIGHT_TILE_WORKGROUP), settings_.chains);
}

}  // namespace gi::gpu
