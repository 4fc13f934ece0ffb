#include "gpu/passes/restir_gi.h"

#include <stdexcept>

#include "gpu/buffer.h"
#include "gpu/shaders/bindings.h"
#include "gpu/shaders/world_cache_bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

std::vector<DescriptorBinding> descriptor_bindings(const std::vector<std::uint32_t>& gi, bool world_cache,
                                                   bool counters) {
  std::vector<DescriptorBinding> b = scene_descriptor_bindings();
  b.push_back({BINDING_GBUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  b.push_back({BINDING_GI_STATS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  if (counters) b.push_back({BINDING_GI_COUNTERS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  for (std::uint32_t n : gi) b.push_back({n, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  // Every GI pass includes world_cache_common.glsl then: the cache's whole table.
  if (world_cache)
    for (std::uint32_t n = BINDING_WC_CHECKSUMS; n <= BINDING_WC_VIEW; ++n)
      b.push_back({n, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return b;
}

const Buffer& buffer_for(std::uint32_t binding, const GiBuffers& b) {
  const Buffer* p = nullptr;
  switch (binding) {
    case BINDING_GI_RESERVOIRS_STORED: p = b.stored; break;
    case BINDING_GI_RESERVOIRS_MID: p = b.mid; break;
    case BINDING_GI_SURFACES: p = b.surfaces; break;
    case BINDING_GI_OUTPUT: p = b.output; break;
    case BINDING_GI_ACCUMULATION: p = b.accumulation; break;
    case BINDING_SPECULAR_OUTPUT: p = b.specular_output; break;
    case BINDING_SPECULAR_ACCUMULATION: p = b.specular_accumulation; break;
    case BINDING_GI_RESERVOIRS_HISTORY: p = b.history; break;
    default: break;
  }
  if (!p) throw std::logic_error("GiPass: no buffer for binding " + std::to_string(binding));
  return *p;
}

}  // namespace

GiPass::GiPass(Device& device, ShaderCompiler& compiler, const GiSettings& settings, const char* name,
               const char* shader, std::vector<std::uint32_t> gi_bindings)
    : chains_(settings.chains),
      world_cache_(settings.queries_world_cache()),
      counters_(settings.path_counters),
      gi_bindings_(std::move(gi_bindings)),
      pass_(device, name, compiler.compile_file(shader, settings.defines()).spirv,
            descriptor_bindings(gi_bindings_, world_cache_, counters_), sizeof(GiPushConstants)) {
  if (world_cache_ && settings.world_cache_defines.empty())
    throw std::logic_error("GiPass: hit_radiance world_cache without the cache's defines (GiSettings::world_cache_defines)");
}

void GiPass::bind(const SceneResources& scene, const GiBuffers& b) {
  pass_.bind_scene(scene);
  pass_.bind_buffer(BINDING_GBUFFER, *b.gbuffer);
  pass_.bind_buffer(BINDING_GI_STATS, *b.stats);
  if (counters_) {
    if (!b.counters) throw std::logic_error("GiPass: path counters compiled in without their buffer");
    pass_.bind_buffer(BINDING_GI_COUNTERS, *b.counters);
  }
  for (std::uint32_t n : gi_bindings_) pass_.bind_buffer(n, buffer_for(n, b));
  if (world_cache_) {
    if (b.world_cache.empty()) throw std::logic_error("GiPass: hit_radiance world_cache without the cache's buffers");
    for (const auto& [n, buffer] : b.world_cache) pass_.bind_buffer(n, *buffer);
  }
}

void GiPass::record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height,
                    const GiPushConstants& push) const {
  pass_.dispatch(cmd, group_count(width, RAY_WORKGROUP_X), group_count(height, RAY_WORKGROUP_Y), chains_, &push);
}

GiInitialTemporal::GiInitialTemporal(Device& device, ShaderCompiler& compiler, const GiSettings& s)
    : GiPass(device, compiler, s, "gi_initial_temporal", kShader,
             {BINDING_GI_RESERVOIRS_STORED, BINDING_GI_RESERVOIRS_MID, BINDING_GI_SURFACES,
              BINDING_GI_RESERVOIRS_HISTORY}) {}

GiSpatialShade::GiSpatialShade(Device& device, ShaderCompiler& compiler, const GiSettings& s)
    : GiPass(device, compiler, s, "gi_spatial_shade", kShader,
             {BINDING_GI_RESERVOIRS_STORED, BINDING_GI_RESERVOIRS_MID, BINDING_GI_SURFACES, BINDING_GI_OUTPUT,
              BINDING_GI_ACCUMULATION, BINDING_GI_RESERVOIRS_HISTORY}) {}

}  // namespace gi::gpu
