// GPU reference mode (gpu/shaders/reference_path_trace.comp): the shared
// unbiased path tracer, counts.z samples per pixel per frame, accumulated into
// two halves by sample-index parity (even -> A, odd -> B; w counts samples),
// non-finite samples counted, never dropped silently.
#pragma once
#include <cstdint>

#include <glm/vec3.hpp>

#include "gpu/compute_pass.h"

namespace gi::gpu {

class Buffer;
class ShaderCompiler;

struct ReferencePathTraceOptions {
  std::uint32_t max_bounces = 32;  // path length cap, as in the Embree reference (compiled in)
  glm::vec3 background{0.0f};      // added where the camera ray misses (Scene::background)
  bool direct_only = false;        // "DI" alone, as the Embree reference's direct-lighting mode
};

class ReferencePathTrace {
 public:
  static constexpr const char* kShader = "gpu/shaders/reference_path_trace.comp";

  ReferencePathTrace(Device& device, ShaderCompiler& compiler, const ReferencePathTraceOptions& options = {});
  // half_a/half_b: vec4 per pixel (rgb sum, w sample count); nonfinite: one uint.
  void bind(const SceneResources& scene, const Buffer& half_a, const Buffer& half_b, const Buffer& nonfinite);
  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) const;

 private:
  ComputePass pass_;
};

}  // namespace gi::gpu
