#include "gpu/passes/specular_gi.h"

namespace gi::gpu {

using namespace gi::shader;

SpecularGi::SpecularGi(Device& device, ShaderCompiler& compiler, const GiSettings& s)
    : GiPass(device, compiler, s, "specular_gi", kShader,
             {BINDING_GI_RESERVOIRS_STORED, BINDING_SPECULAR_OUTPUT, BINDING_SPECULAR_ACCUMULATION}) {}

}  // namespace gi::gpu
