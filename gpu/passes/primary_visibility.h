// Primary visibility (gpu/shaders/primary_visibility.comp): one camera ray per
// pixel centre -> visibility buffer (instance, primitive) and depth.
#pragma once
#include <cstdint>

#include "gpu/compute_pass.h"

namespace gi::gpu {

class Buffer;
class ShaderCompiler;

class PrimaryVisibility {
 public:
  static constexpr const char* kShader = "gpu/shaders/primary_visibility.comp";

  PrimaryVisibility(Device& device, ShaderCompiler& compiler);
  // visibility: uvec2 per pixel; depth: float per pixel.
  void bind(const SceneResources& scene, const Buffer& visibility, const Buffer& depth);
  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) const;

 private:
  ComputePass pass_;
};

}  // namespace gi::gpu
