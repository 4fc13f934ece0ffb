#include "gpu/rc/rc_passes.h"

#include "core/shared/rc/cascades.h"
#include "gpu/shader_compiler.h"

namespace gi::gpu {

RcPass::RcPass(Device& device, ShaderCompiler& compiler, const char* shader, std::vector<std::uint32_t> bindings)
    : pass_(device, std::filesystem::path(shader).stem().string(), compiler.compile_file(shader).spirv,
            [&] {
              std::vector<DescriptorBinding> out;
              for (std::uint32_t b : bindings) out.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
              return out;
            }(),
            sizeof(shader::RcPush)) {}

void RcPass::dispatch(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height,
                      const shader::RcPush& push) const {
  pass_.dispatch(cmd, group_count(width, shader::RC_GROUP), group_count(height, shader::RC_GROUP), 1, &push);
  compute_barrier(cmd);
}

}  // namespace gi::gpu
