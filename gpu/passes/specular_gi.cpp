#include "gpu/passes/specular_gi.h"

namespace gi::gpu {

using namespace gi::shader;

SpecularGi::SpecularGi(Device& device, ShaderCompiler& compiler, const GiSettings& s)
    : GiPass(device, compiler, s, "specular_gi", kShader,
             {{BINDING_GI_RESERVOIRS_STORED, &GiBuffers::stored},
              {BINDING_SPECULAR_OUTPUT, &GiBuffers::specular_output},
              {BINDING_SPECULAR_ACCUMULATION, &GiBuffers::specular_accumulation}}) {}

}  // namespace gi::gpu
