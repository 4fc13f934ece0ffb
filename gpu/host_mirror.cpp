#include "gpu/host_mirror.h"

#include "gpu/device.h"

namespace gi::gpu {

HostMirror::HostMirror(Device& device, const Buffer& source) : source_(&source) {
  if (source.staged()) host_.emplace(device, source.size(), 0, source.name() + " (host mirror)", BufferMemory::staging);
}

void HostMirror::record_copy(VkCommandBuffer cmd) const {
  if (!host_) return;
  VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  before.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  before.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &before, 0,
                       nullptr, 0, nullptr);
  const VkBufferCopy region{0, 0, source_->size()};
  vkCmdCopyBuffer(cmd, source_->handle(), host_->handle(), 1, &region);
  VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  after.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  after.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &after, 0, nullptr, 0,
                       nullptr);
}

}  // namespace gi::gpu
