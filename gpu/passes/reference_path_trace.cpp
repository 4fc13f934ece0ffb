#include "gpu/passes/reference_path_trace.h"

#include <string>

#include <fmt/format.h>

#include "gpu/buffer.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

ComputePass make_pass(Device& device, ShaderCompiler& compiler, const ReferencePathTraceOptions& options) {
  std::vector<DescriptorBinding> bindings = scene_descriptor_bindings();
  bindings.push_back({BINDING_REFERENCE_A, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_REFERENCE_B, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_REFERENCE_NONFINITE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  std::vector<ShaderDefine> defines = {{"REFERENCE_MAX_BOUNCES", std::to_string(options.max_bounces) + "u"}};
  if (options.background != glm::vec3(0.0f))
    defines.push_back({"REFERENCE_BACKGROUND", fmt::format("vec3({:.9g},{:.9g},{:.9g})", options.background.x,
                                                           options.background.y, options.background.z)});
  if (options.direct_only) defines.push_back({"REFERENCE_DIRECT_ONLY", "1"});
  return ComputePass(device, "reference_path_trace", compiler.compile_file(ReferencePathTrace::kShader, defines).spirv,
                     std::move(bindings));
}

}  // namespace

ReferencePathTrace::ReferencePathTrace(Device& device, ShaderCompiler& compiler,
                                       const ReferencePathTraceOptions& options)
    : pass_(make_pass(device, compiler, options)) {}

void ReferencePathTrace::bind(const SceneResources& scene, const Buffer& half_a, const Buffer& half_b,
                              const Buffer& nonfinite) {
  pass_.bind_scene(scene);
  pass_.bind_buffer(BINDING_REFERENCE_A, half_a);
  pass_.bind_buffer(BINDING_REFERENCE_B, half_b);
  pass_.bind_buffer(BINDING_REFERENCE_NONFINITE, nonfinite);
}

void ReferencePathTrace::record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) const {
  pass_.dispatch(cmd, group_count(width, RAY_WORKGROUP_X), group_count(height, RAY_WORKGROUP_Y));
}

}  // namespace gi::gpu
