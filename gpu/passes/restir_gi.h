// ReSTIR GI's two dispatches (docs/design.md §3 step 7): gpu/shaders/gi_initial_temporal.comp
// (initial sample, temporal reuse with permutation sampling) and
// gpu/shaders/gi_spatial_shade.comp (spatial reuse, store, diffuse shading).
#pragma once
#include <cstdint>
#include <vector>

#include "gpu/passes/reservoir_pass.h"
#include "gpu/passes/restir_gi_settings.h"
#include "gpu/shaders/gi_bindings.h"

namespace gi::gpu {

// One GI-family pass: its shader, the GI buffers it reads or writes as slots
// (ReservoirPass: the G-buffer and the statistics, then the pass's own, then
// the path counters where GiSettings::path_counters compiles them in), and
// the world cache's whole table where GI queries it.
class GiPass : public ReservoirPass<GiBuffers, shader::GiPushConstants> {
 public:
  GiPass(Device& device, ShaderCompiler& compiler, const GiSettings& settings, const char* name, const char* shader,
         std::vector<Slot> own);
  void bind(const SceneResources& scene, const GiBuffers& buffers);

 private:
  bool world_cache_;  // the cache's bindings (restir_gi.hit_radiance world_cache)
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
