#include "gpu/timer.h"

#include <fmt/format.h>

#include "core/errors.h"
#include "gpu/device.h"

namespace gi::gpu {

GpuTimer::GpuTimer(Device& device, std::uint32_t max_passes)
    : device_(device.handle()), max_passes_(max_passes), period_ns_(device.info().timestamp_period_ns) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical_device(), &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical_device(), &n, families.data());
  const std::uint32_t bits = families[device.queue_family()].timestampValidBits;
  valid_mask_ = bits >= 64 ? ~0ull : (bits == 0 ? 0ull : ((1ull << bits) - 1));
  VkQueryPoolCreateInfo ci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  ci.queryType = VK_QUERY_TYPE_TIMESTAMP;
  ci.queryCount = 2 * max_passes_;
  check_vk(vkCreateQueryPool(device_, &ci, nullptr, &pool_), "vkCreateQueryPool");
}

GpuTimer::~GpuTimer() {
  if (pool_) vkDestroyQueryPool(device_, pool_, nullptr);
}

void GpuTimer::begin_frame(VkCommandBuffer cmd) {
  names_.clear();
  vkCmdResetQueryPool(cmd, pool_, 0, 2 * max_passes_);
}

void GpuTimer::begin(VkCommandBuffer cmd, std::string name) {
  if (names_.size() >= max_passes_) throw DeviceError(fmt::format("GpuTimer: more than {} passes", max_passes_));
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_, 2 * std::uint32_t(names_.size()));
  names_.push_back(std::move(name));
}

void GpuTimer::end(VkCommandBuffer cmd) {
  vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, 2 * std::uint32_t(names_.size()) - 1);
}

void GpuTimer::resolve() {
  timings_.clear();
  if (names_.empty()) return;
  std::vector<std::uint64_t> ticks(2 * names_.size());
  check_vk(vkGetQueryPoolResults(device_, pool_, 0, std::uint32_t(ticks.size()), ticks.size() * sizeof(std::uint64_t),
                                 ticks.data(), sizeof(std::uint64_t),
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
           "vkGetQueryPoolResults");
  for (std::size_t i = 0; i < names_.size(); ++i) {
    const std::uint64_t dt = ((ticks[2 * i + 1] & valid_mask_) - (ticks[2 * i] & valid_mask_)) & valid_mask_;
    timings_.push_back({names_[i], double(dt) * period_ns_ * 1e-6});
  }
}

}  // namespace gi::gpu
