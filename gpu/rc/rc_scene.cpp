#include "gpu/rc/rc_passes.h"

namespace gi::gpu {

using namespace gi::shader;

RcScene::RcScene(Device& device, ShaderCompiler& compiler, const RcBuffers& b)
    : pass_(device, compiler, kShader, {{BINDING_RC_SHAPES, &b.shapes}, {BINDING_RC_SCENE, &b.scene}}) {}

void RcScene::record(VkCommandBuffer cmd, const RcPush& push) const { pass_.dispatch(cmd, push.width, push.height, push); }

}  // namespace gi::gpu
