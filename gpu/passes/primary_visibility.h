// Primary visibility (gpu/shaders/primary_visibility.comp): one camera ray per
// pixel centre -> visibility buffer (packed cluster ID, instance channel) and
// depth; the cluster table (core/clusters/cluster_ids.h) maps hits to IDs.
#pragma once
#include <cstdint>

#include "gpu/compute_pass.h"

namespace gi::gpu {

class Buffer;
class ShaderCompiler;

class PrimaryVisibility {
 public:
  static constexpr const char* kShader = "gpu/shaders/primary_visibility.comp";

  PrimaryVisibility(Device& device, ShaderCompiler& compiler);
  // visibility: uvec2 per pixel; depth: float per pixel; cluster_table: uint[].
  void bind(const SceneResources& scene, const Buffer& visibility, const Buffer& depth, const Buffer& cluster_table);
  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) const;

 private:
  ComputePass pass_;
};

}  // namespace gi::gpu
