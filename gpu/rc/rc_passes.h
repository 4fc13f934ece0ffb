// The radiance-cascades passes, one driver per GLSL file and
// named after it, as the seed lesson names them: the scene raster (its
// tex_main), the analytic distance field or jump flooding's two passes, the
// cascades (first and merge), the mipmap and the apply. Each driver owns its
// pipeline(s) and binds the buffers once; a pass that ping-pongs (jfa_step,
// rc_cascade) has one pipeline per direction, as the lesson has two bind
// groups, because a descriptor set may not change while recorded.
#pragma once
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/shaders/rc_bindings.h"

namespace gi::gpu {

class ShaderCompiler;

struct RcBuffers {
  Buffer shapes;                  // RcShape[RC_MAX_SHAPES]
  Buffer scene;                   // vec4 per pixel
  Buffer distance;                // float per pixel
  std::array<Buffer, 2> seeds;    // uint per pixel (jfa only)
  std::array<Buffer, 2> cascades; // vec4 per pixel, ping-pong
  Buffer mipmap;                  // vec4 per cascade-0 probe
  Buffer output;                  // vec4 per pixel
};

// One pipeline of an RC pass, its storage buffers bound once, and the
// dispatch over a grid of texels.
class RcPass {
 public:
  using Bindings = std::vector<std::pair<std::uint32_t, const Buffer*>>;
  RcPass(Device& device, ShaderCompiler& compiler, const char* shader, const Bindings& bindings);
  void dispatch(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height, const shader::RcPush& push) const;

 private:
  ComputePass pass_;
};

class RcScene {
 public:
  static constexpr const char* kShader = "gpu/shaders/rc_scene.comp";
  RcScene(Device& device, ShaderCompiler& compiler, const RcBuffers& b);
  void record(VkCommandBuffer cmd, const shader::RcPush& push) const;
 private:
  RcPass pass_;
};

class RcDistance {
 public:
  static constexpr const char* kShader = "gpu/shaders/rc_distance.comp";
  RcDistance(Device& device, ShaderCompiler& compiler, const RcBuffers& b);
  void record(VkCommandBuffer cmd, const shader::RcPush& push) const;
 private:
  RcPass pass_;
};

class JfaSeed {
 public:
  static constexpr const char* kShader = "gpu/shaders/jfa_seed.comp";
  JfaSeed(Device& device, ShaderCompiler& compiler, const RcBuffers& b);  // writes seeds[0]
  void record(VkCommandBuffer cmd, const shader::RcPush& push) const;
 private:
  RcPass pass_;
};

class JfaStep {
 public:
  static constexpr const char* kShader = "gpu/shaders/jfa_step.comp";
  JfaStep(Device& device, ShaderCompiler& compiler, const RcBuffers& b);
  // Every round from the largest power-of-two jump below the canvas's
  // longer side down to 1, starting from seeds[0]; the last writes the distance field.
  void record(VkCommandBuffer cmd, const shader::RcPush& push) const;
  static std::vector<std::uint32_t> jumps(std::uint32_t width, std::uint32_t height);
 private:
  std::array<RcPass, 2> passes_;  // [0]: seeds 0 → 1, [1]: 1 → 0
};

class RcCascade {
 public:
  static constexpr const char* kShader = "gpu/shaders/rc_cascade.comp";
  RcCascade(Device& device, ShaderCompiler& compiler, const RcBuffers& b);
  // One cascade into cascades[into], merging cascades[1 − into] when push.merge.
  void record(VkCommandBuffer cmd, std::uint32_t into, const shader::RcPush& push) const;
 private:
  std::array<RcPass, 2> passes_;  // [i]: writes cascades[i]
};

class RcMipmap {
 public:
  static constexpr const char* kShader = "gpu/shaders/rc_mipmap.comp";
  RcMipmap(Device& device, ShaderCompiler& compiler, const RcBuffers& b);
  void record(VkCommandBuffer cmd, std::uint32_t from, const shader::RcPush& push) const;  // cascades[from]
 private:
  std::array<RcPass, 2> passes_;
};

class RcApply {
 public:
  static constexpr const char* kShader = "gpu/shaders/rc_apply.comp";
  RcApply(Device& device, ShaderCompiler& compiler, const RcBuffers& b);
  void record(VkCommandBuffer cmd, const shader::RcPush& push) const;
 private:
  RcPass pass_;
};

}  // namespace gi::gpu
