// ReSTIR GI's two dispatches (DESIGN §3 step 7): gpu/shaders/gi_initial_temporal.comp
// (initial sample, temporal reuse with permutation sampling) and
// gpu/shaders/gi_spatial_shade.comp (spatial reuse, store, diffuse shading).
#pragma once
#include <cstdint>
#include <vector>

#include "gpu/compute_pass.h"
#include "gpu/passes/restir_gi_settings.h"
#include "gpu/shaders/gi_bindings.h"

namespace gi::gpu {

// One GI-family pass: its shader, the GI buffers it reads or writes (binding
// numbers of gi_bindings.h), the scene and the G-buffer; one invocation per
// pixel and chain.
class GiPass {
 public:
  GiPass(Device& device, ShaderCompiler& compiler, const GiSettings& settings, const char* name, const char* shader,
         std::vector<std::uint32_t> gi_bindings);
  void bind(const SceneResources& scene, const GiBuffers& buffers);
  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height,
              const shader::GiPushConstants& push) const;

 private:
  std::uint32_t chains_;
  bool world_cache_;  // the cache's bindings (restir_gi.hit_radiance world_cache)
  bool counters_;     // GiCounters' binding (GiSettings::path_counters)
  std::vector<std::uint32_t> gi_bindings_;
  ComputePass pass_;
};

class GiInitialTemporal : public GiPass {
 public:
  static constexpr const char* kShader = "gpu/shaders/gi_initial_temporal.comp";
  GiInitialTemporal(Device& device, ShaderCompiler& compiler, const GiSettings& settings);
};

class GiSpatialShade : public GiPass {
 public:
  static constexpr const char* kShader = "gpu/shaders/gi_spatial_shade.comp";
  GiSpatialShade(Device& device, ShaderCompiler& compiler, const GiSettings& settings);
};

}  // namespace gi::gpu
