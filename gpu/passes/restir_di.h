// ReSTIR DI's two dispatches (DESIGN §3 step 6): gpu/shaders/di_initial_temporal.comp
// (initial RIS + shadow ray, temporal reuse) and gpu/shaders/di_spatial_shade.comp
// (spatial reuse, store for next frame, final visibility per profile, shading).
#pragma once
#include <cstdint>

#include "gpu/passes/restir_di_settings.h"
#include "gpu/shaders/di_bindings.h"

namespace gi::gpu {

class DiInitialTemporal {
 public:
  static constexpr const char* kShader = "gpu/shaders/di_initial_temporal.comp";
  DiInitialTemporal(Device& device, ShaderCompiler& compiler, const DiSettings& settings);
  void bind(const SceneResources& scene, const DiBuffers& buffers);
  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height, const shader::DiPushConstants& push) const;

 private:
  DiSettings settings_;
  ComputePass pass_;
};

class DiSpatialShade {
 public:
  static constexpr const char* kShader = "gpu/shaders/di_spatial_shade.comp";
  DiSpatialShade(Device& device, ShaderCompiler& compiler, const DiSettings& settings);
  void bind(const SceneResources& scene, const DiBuffers& buffers);
  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height, const shader::DiPushConstants& push) const;

 private:
  DiSettings settings_;
  ComputePass pass_;
};

}  // namespace gi::gpu
