#include "gpu/passes/restir_di.h"

#include "gpu/buffer.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;

std::vector<DescriptorBinding> common_bindings(const DiSettings& s) {
  std::vector<DescriptorBinding> b = scene_descriptor_bindings();
  for (std::uint32_t n : {BINDING_GBUFFER, BINDING_DI_RESERVOIRS_STORED, BINDING_DI_RESERVOIRS_MID, BINDING_DI_SURFACES})
    b.push_back({n, kStorage});
  if (s.traces_previous_scene()) b.push_back(previous_scene_descriptor_binding());
  return b;
}

void bind_common(ComputePass& pass, const DiSettings& s, const SceneResources& scene, const DiBuffers& b) {
  pass.bind_scene(scene);
  if (s.traces_previous_scene()) pass.bind_previous_scene(scene);
  pass.bind_buffer(BINDING_GBUFFER, *b.gbuffer);
  pass.bind_buffer(BINDING_DI_RESERVOIRS_STORED, *b.stored);
  pass.bind_buffer(BINDING_DI_RESERVOIRS_MID, *b.mid);
  pass.bind_buffer(BINDING_DI_SURFACES, *b.surfaces);
}

ComputePass make_initial(Device& device, ShaderCompiler& compiler, const DiSettings& s) {
  auto b = common_bindings(s);
  for (std::uint32_t n : {BINDING_LIGHT_TILE_SAMPLES, BINDING_LIGHT_TILE_PACKED, BINDING_DI_LIGHT_TRANSLATION})
    b.push_back({n, kStorage});
  return ComputePass(device, "di_initial_temporal", compiler.compile_file(DiInitialTemporal::kShader, s.defines()).spirv,
                     std::move(b), sizeof(DiPushConstants));
}

ComputePass make_spatial(Device& device, ShaderCompiler& compiler, const DiSettings& s) {
  auto b = common_bindings(s);
  for (std::uint32_t n : {BINDING_DI_OUTPUT, BINDING_DI_ACCUMULATION}) b.push_back({n, kStorage});
  return ComputePass(device, "di_spatial_shade", compiler.compile_file(DiSpatialShade::kShader, s.defines()).spirv,
                     std::move(b), sizeof(DiPushConstants));
}

}  // namespace

DiInitialTemporal::DiInitialTemporal(Device& device, ShaderCompiler& compiler, const DiSettings& settings)
    : settings_(settings), pass_(make_initial(device, compiler, settings)) {}

void DiInitialTemporal::bind(const SceneResources& scene, const DiBuffers& b) {
  bind_common(pass_, settings_, scene, b);
  pass_.bind_buffer(BINDING_LIGHT_TILE_SAMPLES, *b.tile_samples);
  pass_.bind_buffer(BINDING_LIGHT_TILE_PACKED, *b.tile_packed);
  pass_.bind_buffer(BINDING_DI_LIGHT_TRANSLATION, *b.translation);
}

void DiInitialTemporal::record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height,
                               const DiPushConstants& push) const {
  pass_.dispatch(cmd, group_count(width, RAY_WORKGROUP_X), group_count(height, RAY_WORKGROUP_Y), settings_.chains,
                 &push);
}

DiSpatialShade::DiSpatialShade(Device& device, ShaderCompiler& compiler, const DiSettings& settings)
    : settings_(settings), pass_(make_spatial(device, compiler, settings)) {}

void DiSpatialShade::bind(const SceneResources& scene, const DiBuffers& b) {
  bind_common(pass_, settings_, scene, b);
  pass_.bind_buffer(BINDING_DI_OUTPUT, *b.output);
  pass_.bind_buffer(BINDING_DI_ACCUMULATION, *b.accumulation);
}

void DiSpatialShade::record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height,
                            const DiPushConstants& push) const {
  pass_.dispatch(cmd, group_count(width, RAY_WORKGROUP_X), group_count(height, RAY_WORKGROUP_Y), settings_.chains,
                 &push);
}

}  // namespace gi::gpu
