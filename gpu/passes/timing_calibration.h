// The timing calibration kernel (gpu/shaders/timing_calibration.comp): a
// fixed workload dispatched and timed at the end of every frame on a CPU
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
  // About 1.5 ms on lavapipe with 2 threads, 1 ms of it the loop (3.1 us
  // per iteration of all invocations) and the rest the fixed cost of any
  // dispatch. At 40-96 iterations the fixed cost was all of it (0.45-0.6 ms
  // whatever the count), which tracks thread wake-ups, not speed: the
  // nightly's ratios drifted 2x between runs of an unchanged tree.
  static constexpr std::uint32_t kInvocations = 2048;
  static constexpr std::uint32_t kIterations = 300;

  TimingCalibration(Device& device, ShaderCompiler& compiler);
  // Timed under kTimerName, then a barrier (the frame's first pass waits for it).
  void record(VkCommandBuffer cmd, GpuTimer& timer) const;

 private:
  Buffer table_;
  ComputePass pass_;
};

}  // namespace gi::gpu
