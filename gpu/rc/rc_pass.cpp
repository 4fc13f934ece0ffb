#include "gpu/rc/rc_passes.h"

#include "core/shared/rc/cascades.h"
#include "gpu/shader_compiler.h"

namespace gi::gpu {

namespace {

std::vector<DescriptorBinding> storage(const RcPass::Bindings& bindings) {
  std::vector<DescriptorBinding> out;
  for (const auto& [binding, _] : bindings) out.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return out;
}

}  // namespace

RcPass::RcPass(Device& device, ShaderCompiler& compiler, const char* shader, const Bindings& bindings)
    : pass_(device, std::filesystem::path(shader).stem().string(), compiler.compile_file(shader).spirv,
            storage(bindings), sizeof(shader::RcPush)) {
  for (const auto& [binding, buffer] : bindings) pass_.bind_buffer(binding, *buffer);
}

void RcPass::dispatch(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height,
                      const shader::RcPush& push) const {
  pass_.dispatch(cmd, group_count(width, shader::RC_GROUP), group_count(height, shader::RC_GROUP), 1, &push);
  compute_barrier(cmd);
}

}  // namespace gi::gpu
