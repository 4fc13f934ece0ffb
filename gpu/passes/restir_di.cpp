#include "gpu/passes/restir_di.h"

#include "gpu/buffer.h"
#include "gpu/shader_compiler.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

std::vector<DescriptorBinding> previous_scene(const DiSettings& s) {
  if (!s.traces_previous_scene()) return {};
  return {previous_scene_descriptor_binding()};
}

}  // namespace

DiPass::DiPass(Device& device, ShaderCompiler& compiler, const DiSettings& s, const char* name, const char* shader,
               std::vector<Slot> slots)
    : ReservoirPass(device, name, compiler.compile_file(shader, s.defines()).spirv, std::move(slots),
                    previous_scene(s), s.chains),
      previous_scene_(s.traces_previous_scene()) {}

void DiPass::bind(const SceneResources& scene, const DiBuffers& b) {
  bind_slots(scene, b);
  if (previous_scene_) pass().bind_previous_scene(scene);
}

DiInitialTemporal::DiInitialTemporal(Device& device, ShaderCompiler& compiler, const DiSettings& s)
    : DiPass(device, compiler, s, "di_initial_temporal", kShader,
             {{BINDING_GBUFFER, &DiBuffers::gbuffer},
              {BINDING_DI_RESERVOIRS_STORED, &DiBuffers::stored},
              {BINDING_DI_RESERVOIRS_MID, &DiBuffers::mid},
              {BINDING_DI_SURFACES, &DiBuffers::surfaces},
              {BINDING_LIGHT_TILE_SAMPLES, &DiBuffers::tile_samples},
              {BINDING_LIGHT_TILE_PACKED, &DiBuffers::tile_packed},
              {BINDING_DI_LIGHT_TRANSLATION, &DiBuffers::translation}}) {}

DiSpatialShade::DiSpatialShade(Device& device, ShaderCompiler& compiler, const DiSettings& s)
    : DiPass(device, compiler, s, "di_spatial_shade", kShader,
             {{BINDING_GBUFFER, &DiBuffers::gbuffer},
              {BINDING_DI_RESERVOIRS_STORED, &DiBuffers::stored},
              {BINDING_DI_RESERVOIRS_MID, &DiBuffers::mid},
              {BINDING_DI_SURFACES, &DiBuffers::surfaces},
              {BINDING_DI_OUTPUT, &DiBuffers::output},
              {BINDING_DI_ACCUMULATION, &DiBuffers::accumulation}}) {}

}  // namespace gi::gpu
