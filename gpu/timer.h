// Per-pass GPU timestamps: a query pool, one timestamp before and one after
// each pass, read back (after the frame's submission has finished) in ms via
// timestampPeriod. Timings are of the last frame only.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gi::gpu {

class Device;

struct PassTiming {
  std::string name;
  double ms = 0.0;
};

class GpuTimer {
 public:
  GpuTimer(Device& device, std::uint32_t max_passes = 32);
  ~GpuTimer();
  GpuTimer(const GpuTimer&) = delete;
  GpuTimer& operator=(const GpuTimer&) = delete;

  // Recording: begin_frame once, then begin/end around each pass.
  void begin_frame(VkCommandBuffer cmd);
  void begin(VkCommandBuffer cmd, std::string name);
  void end(VkCommandBuffer cmd);
  // After the submission has completed: fills timings().
  void resolve();

  const std::vector<PassTiming>& timings() const { return timings_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  std::uint32_t max_passes_ = 0;
  double period_ns_ = 1.0;
  std::uint64_t valid_mask_ = ~0ull;
  std::vector<std::string> names_;  // passes recorded this frame
  std::vector<PassTiming> timings_;
};

}  // namespace gi::gpu
