// ReSTIR DI's two dispatches (docs/design.md §3 step 6): gpu/shaders/di_initial_temporal.comp
// (initial RIS + shadow ray, temporal reuse) and gpu/shaders/di_spatial_shade.comp
// (spatial reuse, store for next frame, final visibility per profile, shading).
#pragma once
#include <cstdint>
#include <vector>

#include "gpu/passes/reservoir_pass.h"
#include "gpu/passes/restir_di_settings.h"
#include "gpu/shaders/di_bindings.h"

namespace gi::gpu {

// One DI pass: its shader, the DI buffers it reads or writes as slots
// (ReservoirPass), and last frame's scene where the profile traces it
// (DiSettings::traces_previous_scene).
class DiPass : public ReservoirPass<DiBuffers, shader::DiPushConstants> {
 public:
  DiPass(Device& device, ShaderCompiler& compiler, const DiSettings& settings, const char* name, const char* shader,
         std::vector<Slot> slots);
  void bind(const SceneResources& scene, const DiBuffers& buffers);

 private:
  bool previous_scene_;
};

class DiInitialTemporal : public DiPass {
 public:
  static constexpr const char* kShader = "gpu/shaders/di_initial_temporal.comp";
  DiInitialTemporal(Device& device, ShaderCompiler& compiler, const DiSettings& settings);
};

class DiSpatialShade : public DiPass {
 public:
  static constexpr const char* kShader = "gpu/shaders/di_spatial_shade.comp";
  DiSpatialShade(Device& device, ShaderCompiler& compiler, const DiSettings& settings);
};

}  // namespace gi::gpu
