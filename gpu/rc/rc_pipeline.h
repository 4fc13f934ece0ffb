// The radiance-cascades pipeline on one device: its buffers and
// passes (gpu/rc/rc_passes.h) in the lesson's order — scene raster, distance
// field (analytic, or jump flooding), cascades from the farthest down with
// merging, mipmap, apply — recorded into one submission per frame.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/rc/canvas.h"
#include "core/rc/rc_settings.h"
#include "gpu/rc/rc_passes.h"

namespace gi::gpu {

class Device;
class GpuTimer;
class ShaderCompiler;

class RcPipeline {
 public:
  RcPipeline(Device& device, ShaderCompiler& compiler, const RcSettings& settings);

  // The canvas's shapes for the next frames (an upload: between frames).
  void set_canvas(const Canvas& canvas);
  // The frame's passes; `timer` (optional) times each. `after_cascade`, when
  // given, is called after each cascade's pass has been recorded with the
  // cascade and the buffer it wrote (a capture copies it out there).
  void record(VkCommandBuffer cmd, GpuTimer* timer = nullptr,
              const std::function<void(VkCommandBuffer, std::uint32_t, const Buffer&)>& after_cascade = {}) const;

  const RcSettings& settings() const { return settings_; }
  const RcBuffers& buffers() const { return buffers_; }
  std::uint32_t cascade0_buffer() const;  // which of buffers().cascades holds cascade 0 after record()

  // Readbacks (between frames).
  Image output() const;
  Image scene() const;
  std::vector<float> distance() const;
  Image cascade0() const;
  Image mipmap() const;  // mip_width × mip_height

 private:
  shader::RcPush push_for(std::uint32_t cascade) const;

  Device& device_;
  RcSettings settings_;
  std::uint32_t shape_count_ = 0;
  RcBuffers buffers_;
  RcScene scene_;
  std::optional<RcDistance> distance_;
  std::optional<JfaSeed> jfa_seed_;
  std::optional<JfaStep> jfa_step_;
  RcCascade cascade_;
  RcMipmap mipmap_;
  RcApply apply_;
};

// A buffer of vec4 texels as an image (alpha dropped).
Image rc_image(const Buffer& buffer, std::uint32_t width, std::uint32_t height);

}  // namespace gi::gpu
