// The frame's output and its measures, made on the GPU (gpu/shaders/
// frame_output.comp): the output image (realtime: chain A's (DI + GI) +
// specular; reference: the halves' mean), each signal's luminance summed
// over finite pixels (double, fixed order), the output's non-finite
// channels, the image's hash (gpu/passes/buffer_hash.h), and in the temporal
// noise window each pixel's running sums. Recorded at the end of the
// frame's command buffer; after the submission, measures() reads a few
// dozen mapped bytes. The image and the noise sums are read back only when
// asked (a check judging the frame, a capture, the run's end).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/passes/buffer_hash.h"
#include "gpu/host_mirror.h"

namespace gi::gpu {

class GpuTimer;
class ShaderCompiler;

// What the frame record reads of every frame.
struct FrameMeasures {
  // Mean luminance over finite pixels (0 with none), per signal; GI and
  // specular only with GI, DI only in realtime.
  double output_luminance = 0, di_luminance = 0, gi_luminance = 0, specular_luminance = 0;
  std::uint64_t nonfinite_components = 0;  // of the output (core/metrics.h count_nonfinite)
  std::string image_hash;                  // word_hash of the output's rgb floats
};

// Per pixel of each signal: the sums of x and x² since the noise window began.
struct NoiseSums {
  std::vector<glm::dvec3> sum, sum_sq;
};

class FrameOutput {
 public:
  static constexpr const char* kShader = "gpu/shaders/frame_output.comp";

  enum class Mode { di, di_gi, reference };
  FrameOutput(Device& device, ShaderCompiler& compiler, std::uint32_t width, std::uint32_t height, Mode mode);

  // Realtime: chain A is each buffer's first width·height vec4s. Reference:
  // the halves' sums (rgb, w samples); gi and specular unused.
  void bind(const Buffer& signal0, const Buffer* signal1, const Buffer* signal2);
  // The temporal noise window: restart zeroes the sums (between frames);
  // while accumulating, every recorded frame adds its signals.
  void restart_noise();
  void set_accumulate_noise(bool on) { accumulate_noise_ = on; }
  void record(VkCommandBuffer cmd, GpuTimer& timer);

  // After the frame's submission.
  FrameMeasures measures() const;
  Image image() const;  // full readback
  // {signal name: sums}: "output", "di", and with GI "gi", "specular" (full readback).
  std::map<std::string, NoiseSums> noise_sums() const;
  const Buffer& image_buffer() const { return image_; }

 private:
  std::uint32_t pixels() const { return width_ * height_; }
  std::uint32_t signals() const;

  std::uint32_t width_, height_;
  Mode mode_;
  ComputePass pass_, reduce_;
  BufferHash hash_;
  Buffer image_, partials_, results_, noise_;
  HostMirror results_host_;
  bool accumulate_noise_ = false;
};

}  // namespace gi::gpu
