#include "gpu/rc/rc_passes.h"

namespace gi::gpu {

using namespace gi::shader;

RcMipmap::RcMipmap(Device& device, ShaderCompiler& compiler, const RcBuffers& b)
    : passes_{RcPass(device, compiler, kShader, {{BINDING_RC_CASCADE_SOURCE, &b.cascades[0]}, {BINDING_RC_MIPMAP, &b.mipmap}}),
              RcPass(device, compiler, kShader, {{BINDING_RC_CASCADE_SOURCE, &b.cascades[1]}, {BINDING_RC_MIPMAP, &b.mipmap}})} {}

void RcMipmap::record(VkCommandBuffer cmd, std::uint32_t from, const RcPush& push) const {
  passes_[from].dispatch(cmd, push.mip_width, push.mip_height, push);
}

}  // namespace gi::gpu
