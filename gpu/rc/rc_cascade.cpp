#include "gpu/rc/rc_passes.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

RcPass make(Device& device, ShaderCompiler& compiler, const RcBuffers& b, int into) {
  RcPass p(device, compiler, RcCascade::kShader,
           {BINDING_RC_SCENE, BINDING_RC_DISTANCE, BINDING_RC_CASCADE_SOURCE, BINDING_RC_CASCADE_DEST});
  p.bind(BINDING_RC_SCENE, b.scene);
  p.bind(BINDING_RC_DISTANCE, b.distance);
  p.bind(BINDING_RC_CASCADE_SOURCE, b.cascades[1 - into]);
  p.bind(BINDING_RC_CASCADE_DEST, b.cascades[into]);
  return p;
}

}  // namespace

RcCascade::RcCascade(Device& device, ShaderCompiler& compiler, const RcBuffers& b)
    : passes_{make(device, compiler, b, 0), make(device, compiler, b, 1)} {}

void RcCascade::record(VkCommandBuffer cmd, std::uint32_t into, const RcPush& push) const {
  passes_[into].dispatch(cmd, push.width, push.height, push);
}

}  // namespace gi::gpu
