// Light tiles (gpu/shaders/light_tiles.comp): settings.tile_count ×
// settings.samples_per_tile presampled, resolved, packed light samples per DI chain.
#pragma once
#include <cstdint>

#include "gpu/passes/restir_di_settings.h"

namespace gi::gpu {

class LightTiles {
 public:
  static constexpr const char* kShader = "gpu/shaders/light_tiles.comp";
  LightTiles(Device& device, ShaderCompiler& compiler, const DiSettings& settings);
  void bind(const SceneResources& scene, const DiBuffers& buffers);
  void record(VkCommandBuffer cmd) const;

 private:
  DiSettings settings_;
  ComputePass pass_;
};

}  // namespace gi::gpu
