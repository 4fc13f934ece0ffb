// The timing calibration kernel (gpu/shaders/timing_calibration.comp): a
// fixed workload dispatched and timed at the start of every frame on a CPU
// device (lavapipe), so the nightly can read pass times as multiples of the
// machine's current speed (reports/timing_verdict.h). Renderer records it
// under kTimerName and keeps it out of the frame's pass timings.
#pragma once
#include <cstdint>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"

namespace gi::gpu {

class GpuTimer;
class ShaderCompiler;

class TimingCalibration {
 public:
  static constexpr const char* kShader = "gpu/shaders/timing_calibration.comp";
  static constexpr const char* kTimerName = "timing_calibration";
  // About 0.25 ms on lavapipe with 2 threads (0.6 ms at 96 iterations):
  // long enough that timestamp jitter stays small beside it, short beside
  // a frame; the nightly takes a 9-frame median of it, not one frame's.
  static constexpr std::uint32_t kInvocations = 2048;
  static constexpr std::uint32_t kIterations = 40;

  TimingCalibration(Device& device, ShaderCompiler& compiler);
  // Timed under kTimerName, then a barrier (the frame's first pass waits for it).
  void record(VkCommandBuffer cmd, GpuTimer& timer) const;

 private:
  Buffer table_;
  ComputePass pass_;
};

}  // namespace gi::gpu
