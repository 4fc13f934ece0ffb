// Specular GI (docs/design.md §3 step 8): gpu/shaders/specular_gi.comp, after ReSTIR
// GI's spatial pass (rough pixels reuse its final reservoir).
#pragma once
#include "gpu/passes/restir_gi.h"

namespace gi::gpu {

class SpecularGi : public GiPass {
 public:
  static constexpr const char* kShader = "gpu/shaders/specular_gi.comp";
  SpecularGi(Device& device, ShaderCompiler& compiler, const GiSettings& settings);
};

}  // namespace gi::gpu
