#include "gpu/passes/primary_visibility.h"

#include "gpu/buffer.h"
#include "gpu/shader_compiler.h"
#include "core/clusters/cluster_ids.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

ComputePass make_pass(Device& device, ShaderCompiler& compiler) {
  std::vector<DescriptorBinding> bindings = scene_descriptor_bindings();
  bindings.push_back({BINDING_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_DEPTH, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_CLUSTER_TABLE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return ComputePass(device, "primary_visibility", compiler.compile_file(PrimaryVisibility::kShader).spirv,
                     std::move(bindings));
}

}  // namespace

PrimaryVisibility::PrimaryVisibility(Device& device, ShaderCompiler& compiler) : pass_(make_pass(device, compiler)) {}

void PrimaryVisibility::bind(const SceneResources& scene, const Buffer& visibility, const Buffer& depth,
                             const Buffer& cluster_table) {
  pass_.bind_scene(scene);
  pass_.bind_buffer(BINDING_VISIBILITY, visibility);
  pass_.bind_buffer(BINDING_DEPTH, depth);
  pass_.bind_buffer(BINDING_CLUSTER_TABLE, cluster_table);
}

void PrimaryVisibility::record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height) const {
  pass_.dispatch(cmd, group_count(width, RAY_WORKGROUP_X), group_count(height, RAY_WORKGROUP_Y));
}

}  // namespace gi::gpu
