#include "gpu/rc/rc_passes.h"

#include <algorithm>

namespace gi::gpu {

using namespace gi::shader;

JfaStep::JfaStep(Device& device, ShaderCompiler& compiler, const RcBuffers& b)
    : passes_{RcPass(device, compiler, kShader,
                     {{BINDING_RC_SEEDS_IN, &b.seeds[0]}, {BINDING_RC_SEEDS_OUT, &b.seeds[1]}, {BINDING_RC_DISTANCE, &b.distance}}),
              RcPass(device, compiler, kShader,
                     {{BINDING_RC_SEEDS_IN, &b.seeds[1]}, {BINDING_RC_SEEDS_OUT, &b.seeds[0]}, {BINDING_RC_DISTANCE, &b.distance}})} {}

std::vector<std::uint32_t> JfaStep::jumps(std::uint32_t width, std::uint32_t height) {
  std::uint32_t k = 1;
  while (k * 2 < std::max(width, height)) k *= 2;
  std::vector<std::uint32_t> out;
  for (; k >= 1; k /= 2) out.push_back(k);
  return out;
}

void JfaStep::record(VkCommandBuffer cmd, const RcPush& base) const {
  const std::vector<std::uint32_t> ks = jumps(base.width, base.height);
  for (std::size_t i = 0; i < ks.size(); ++i) {
    RcPush push = base;
    push.jfa_step = ks[i];
    push.jfa_last = i + 1 == ks.size() ? 1u : 0u;
    passes_[i % 2].dispatch(cmd, push.width, push.height, push);
  }
}

}  // namespace gi::gpu
