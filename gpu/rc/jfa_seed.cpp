#include "gpu/rc/rc_passes.h"

namespace gi::gpu {

using namespace gi::shader;

JfaSeed::JfaSeed(Device& device, ShaderCompiler& compiler, const RcBuffers& b)
    : pass_(device, compiler, kShader, {{BINDING_RC_SCENE, &b.scene}, {BINDING_RC_SEEDS_OUT, &b.seeds[0]}}) {}

void JfaSeed::record(VkCommandBuffer cmd, const RcPush& push) const { pass_.dispatch(cmd, push.width, push.height, push); }

}  // namespace gi::gpu
