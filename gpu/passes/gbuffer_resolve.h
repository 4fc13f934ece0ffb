// G-buffer resolve (gpu/shaders/gbuffer_resolve.comp): visibility buffer ->
// one GBufferTexel per pixel (gpu/shaders/gbuffer.h), motion vectors from the
// previous camera and each instance's previous transform.
#pragma once
#include <cstdint>

#include "gpu/compute_pass.h"
#include "gpu/shaders/gbuffer.h"

namespace gi::gpu {

using shader::GBufferTexel;
static_assert(sizeof(GBufferTexel) == 96, "GBufferTexel must stay whole vec4s (std430 == C++)");

class Buffer;
class ShaderCompiler;

// The profile's temporal.motion_vectors: where the surface point was last
// frame (its instance's previous transform) in the previous view, as Bevy's
// prepass; the previous view alone (camera motion only, the harness's earlier
// model); or none (a reprojection bug: history read at the pixel).
enum class MotionVectors { object, camera, ignored };

class GBufferResolve {
 public:
  static constexpr const char* kShader = "gpu/shaders/gbuffer_resolve.comp";

  GBufferResolve(Device& device, ShaderCompiler& compiler, MotionVectors motion = MotionVectors::object);
  // visibility/depth/cluster_table as PrimaryVisibility uses them; gbuffer: GBufferTexel per pixel;
  // previous_transforms: FlatInstances::previous_object_to_world (mat4 per instance).
  void bind(const SceneResources& scene, const Buffer& visibility, const Buffer& depth, const Buffer& gbuffer,
            const Buffer& cluster_table, const Buffer& previous_transforms);
  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) const;

 private:
  ComputePass pass_;
};

}  // namespace gi::gpu
