#include "gpu/rc/rc_passes.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

RcPass make(Device& device, ShaderCompiler& compiler, const RcBuffers& b, int from) {
  RcPass p(device, compiler, RcMipmap::kShader, {BINDING_RC_CASCADE_SOURCE, BINDING_RC_MIPMAP});
  p.bind(BINDING_RC_CASCADE_SOURCE, b.cascades[from]);
  p.bind(BINDING_RC_MIPMAP, b.mipmap);
  return p;
}

}  // namespace

RcMipmap::RcMipmap(Device& device, ShaderCompiler& compiler, const RcBuffers& b)
    : passes_{make(device, compiler, b, 0), make(device, compiler, b, 1)} {}

void RcMipmap::record(VkCommandBuffer cmd, std::uint32_t from, const RcPush& push) const {
  passes_[from].dispatch(cmd, push.mip_width, push.mip_height, push);
}

}  // namespace gi::gpu
