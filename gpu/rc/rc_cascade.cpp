#include "gpu/rc/rc_passes.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

// Writes cascades[into], merging from the other buffer.
RcPass::Bindings bindings(const RcBuffers& b, int into) {
  return {{BINDING_RC_SCENE, &b.scene},
          {BINDING_RC_DISTANCE, &b.distance},
          {BINDING_RC_CASCADE_SOURCE, &b.cascades[1 - into]},
          {BINDING_RC_CASCADE_DEST, &b.cascades[into]}};
}

}  // namespace

RcCascade::RcCascade(Device& device, ShaderCompiler& compiler, const RcBuffers& b)
    : passes_{RcPass(device, compiler, kShader, bindings(b, 0)), RcPass(device, compiler, kShader, bindings(b, 1))} {}

void RcCascade::record(VkCommandBuffer cmd, std::uint32_t into, const RcPush& push) const {
  passes_[into].dispatch(cmd, push.width, push.height, push);
}

}  // namespace gi::gpu
