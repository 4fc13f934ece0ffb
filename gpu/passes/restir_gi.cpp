#include "gpu/passes/restir_gi.h"

#include <stdexcept>

#include "gpu/buffer.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/world_cache_bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

using Slot = GiPass::Slot;

std::vector<Slot> slots(const GiSettings& s, std::vector<Slot> own) {
  std::vector<Slot> all = {{BINDING_GBUFFER, &GiBuffers::gbuffer}, {BINDING_GI_STATS, &GiBuffers::stats}};
  all.insert(all.end(), own.begin(), own.end());
  if (s.path_counters) all.push_back({BINDING_GI_COUNTERS, &GiBuffers::counters});
  return all;
}

// Every GI pass includes world_cache_common.glsl then: the cache's whole table.
std::vector<DescriptorBinding> world_cache_bindings(bool world_cache) {
  std::vector<DescriptorBinding> b;
  if (world_cache)
    for (std::uint32_t n = BINDING_WC_CHECKSUMS; n <= BINDING_WC_VIEW; ++n)
      b.push_back({n, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return b;
}

}  // namespace

GiPass::GiPass(Device& device, ShaderCompiler& compiler, const GiSettings& s, const char* name, const char* shader,
               std::vector<Slot> own)
    : ReservoirPass(device, name, compiler.compile_file(shader, s.defines()).spirv, slots(s, std::move(own)),
                    world_cache_bindings(s.queries_world_cache()), s.chains),
      world_cache_(s.queries_world_cache()) {
  if (world_cache_ && s.world_cache_defines.empty())
    throw std::logic_error("GiPass: hit_radiance world_cache without the cache's defines (GiSettings::world_cache_defines)");
}

void GiPass::bind(const SceneResources& scene, const GiBuffers& b) {
  bind_slots(scene, b);
  if (world_cache_) {
    if (b.world_cache.empty()) throw std::logic_error("GiPass: hit_radiance world_cache without the cache's buffers");
    for (const auto& [n, buffer] : b.world_cache) pass().bind_buffer(n, *buffer);
  }
}

GiInitialTemporal::GiInitialTemporal(Device& device, ShaderCompiler& compiler, const GiSettings& s)
    : GiPass(device, compiler, s, "gi_initial_temporal", kShader,
             {{BINDING_GI_RESERVOIRS_STORED, &GiBuffers::stored},
              {BINDING_GI_RESERVOIRS_MID, &GiBuffers::mid},
              {BINDING_GI_SURFACES, &GiBuffers::surfaces},
              {BINDING_GI_RESERVOIRS_HISTORY, &GiBuffers::history}}) {}

GiSpatialShade::GiSpatialShade(Device& device, ShaderCompiler& compiler, const GiSettings& s)
    : GiPass(device, compiler, s, "gi_spatial_shade", kShader,
             {{BINDING_GI_RESERVOIRS_STORED, &GiBuffers::stored},
              {BINDING_GI_RESERVOIRS_MID, &GiBuffers::mid},
              {BINDING_GI_SURFACES, &GiBuffers::surfaces},
              {BINDING_GI_OUTPUT, &GiBuffers::output},
              {BINDING_GI_ACCUMULATION, &GiBuffers::accumulation},
              {BINDING_GI_RESERVOIRS_HISTORY, &GiBuffers::history}}) {}

}  // namespace gi::gpu
