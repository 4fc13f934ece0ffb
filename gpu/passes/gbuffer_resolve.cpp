#include "gpu/passes/gbuffer_resolve.h"

#include "gpu/buffer.h"
#include "gpu/shader_compiler.h"
#include "core/clusters/cluster_ids.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

ComputePass make_pass(Device& device, ShaderCompiler& compiler, MotionVectors motion) {
  std::vector<DescriptorBinding> bindings = scene_descriptor_bindings();
  bindings.push_back({BINDING_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_DEPTH, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_GBUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_CLUSTER_TABLE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_PREVIOUS_TRANSFORMS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  std::vector<ShaderDefine> defines;
  if (motion == MotionVectors::object) defines.push_back({"GBUFFER_MOTION_OBJECT", ""});
  if (motion == MotionVectors::ignored) defines.push_back({"GBUFFER_MOTION_IGNORED", ""});
  return ComputePass(device, "gbuffer_resolve", compiler.compile_file(GBufferResolve::kShader, defines).spirv,
                     std::move(bindings));
}

}  // namespace

GBufferResolve::GBufferResolve(Device& device, ShaderCompiler& compiler, MotionVectors motion)
    : pass_(make_pass(device, compiler, motion)) {}

void GBufferResolve::bind(const SceneResources& scene, const Buffer& visibility, const Buffer& depth,
                          const Buffer& gbuffer, const Buffer& cluster_table, const Buffer& previous_transforms) {
  pass_.bind_buffer(BINDING_CLUSTER_TABLE, cluster_table);
  pass_.bind_buffer(BINDING_PREVIOUS_TRANSFORMS, previous_transforms);
  pass_.bind_scene(scene);
  pass_.bind_buffer(BINDING_VISIBILITY, visibility);
  pass_.bind_buffer(BINDING_DEPTH, depth);
  pass_.bind_buffer(BINDING_GBUFFER, gbuffer);
}

void GBufferResolve::record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) const {
  pass_.dispatch(cmd, group_count(width, RAY_WORKGROUP_X), group_count(height, RAY_WORKGROUP_Y));
}

}  // namespace gi::gpu
