#include "gpu/buffer.h"

#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "gpu/device.h"

namespace gi::gpu {

namespace {

// The first memory type allowed for the buffer with every flag of the first
// wish that any allowed type satisfies (and none of `avoid` for that wish).
struct MemoryWish {
  VkMemoryPropertyFlags want, avoid;
};

std::uint32_t pick_memory_type(VkPhysicalDevice pd, std::uint32_t allowed, std::initializer_list<MemoryWish> wishes,
                               const std::string& name) {
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(pd, &mp);
  for (const MemoryWish& w : wishes)
    for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i) {
      const VkMemoryPropertyFlags f = mp.memoryTypes[i].propertyFlags;
      if ((allowed & (1u << i)) && (f & w.want) == w.want && !(f & w.avoid)) return i;
    }
  throw DeviceError(fmt::format("Vulkan: no suitable memory type for buffer '{}'", name));
}

constexpr VkMemoryPropertyFlags kLocal = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr VkMemoryPropertyFlags kCached = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;

std::uint32_t memory_type(const Device& device, std::uint32_t allowed, bool mapped, BufferMemory use,
                          const std::string& name) {
  const VkPhysicalDevice pd = device.physical_device();
  if (!mapped) return pick_memory_type(pd, allowed, {{kLocal, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT}, {kLocal, 0}}, name);
  if (use == BufferMemory::staging) return pick_memory_type(pd, allowed, {{kHost | kCached, 0}, {kHost, 0}}, name);
  return pick_memory_type(pd, allowed, {{kLocal | kHost, 0}, {kHost, 0}}, name);
}

// Orders a transfer after every earlier command's writes and every later
// command (and the host, for readbacks) after the transfer.
void barrier(VkCommandBuffer cmd, VkPipelineStageFlags dst_stage, VkAccessFlags dst_access) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, dst_stage, 0, 1, &b, 0, nullptr, 0, nullptr);
}

void before_transfer(VkCommandBuffer cmd) {
  barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
}

void after_transfer(VkCommandBuffer cmd) {
  barrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT,
          VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT | VK_ACCESS_HOST_READ_BIT);
}

}  // namespace

Buffer::Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, std::string name, BufferMemory memory)
    : owner_(&device), device_(device.handle()), size_(size == 0 ? 16 : size), name_(std::move(name)) {
  const bool mapped = memory != BufferMemory::device || !device.staged_buffers();
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = size_;
  // Every buffer has a device address: the buffer hash (gpu/passes/buffer_hash.h) reads any buffer through it.
  usage |= VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  bci.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check_vk(vkCreateBuffer(device_, &bci, nullptr, &buffer_), "vkCreateBuffer");
  try {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, buffer_, &req);
    const bool want_address = usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.pNext = want_address ? &flags : nullptr;
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = memory_type(device, req.memoryTypeBits, mapped, memory, name_);
    check_vk(vkAllocateMemory(device_, &mai, nullptr, &memory_), "vkAllocateMemory");
    check_vk(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory");
    if (mapped) check_vk(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
    if (want_address) {
      VkBufferDeviceAddressInfo ai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
      ai.buffer = buffer_;
      address_ = vkGetBufferDeviceAddress(device_, &ai);
    }
  } catch (...) {
    destroy();
    throw;
  }
}

void Buffer::destroy() noexcept {
  if (device_) {
    if (mapped_) vkUnmapMemory(device_, memory_);
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
  }
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  address_ = 0;
}

Buffer::~Buffer() { destroy(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    destroy();
    owner_ = std::exchange(other.owner_, nullptr);
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    address_ = std::exchange(other.address_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
    name_ = std::move(other.name_);
  }
  return *this;
}

void Buffer::upload_bytes(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (offset + bytes > size_)
    throw DeviceError(fmt::format("buffer '{}': upload of {} bytes at {} exceeds its {} bytes", name_, bytes, offset,
                                  size_));
  if (!bytes) return;
  owner_->count_transfer(false, bytes);
  if (mapped_) {
    owner_->wait();  // never under a submission in flight (a no-op when none is)
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    return;
  }
  Buffer& staging = owner_->staging(bytes);
  std::memcpy(staging.mapped_, data, bytes);
  owner_->submit_and_wait([&](VkCommandBuffer cmd) {
    before_transfer(cmd);
    const VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cmd, staging.buffer_, buffer_, 1, &region);
    after_transfer(cmd);
  });
}

void Buffer::download_bytes(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (offset + bytes > size_)
    throw DeviceError(fmt::format("buffer '{}': download of {} bytes at {} exceeds its {} bytes", name_, bytes,
                                  offset, size_));
  if (!bytes) return;
  owner_->count_transfer(true, bytes);
  if (mapped_) {
    owner_->wait();  // never under a submission in flight (a no-op when none is)
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  Buffer& staging = owner_->staging(bytes);
  owner_->submit_and_wait([&](VkCommandBuffer cmd) {
    before_transfer(cmd);
    const VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cmd, buffer_, staging.buffer_, 1, &region);
    after_transfer(cmd);
  });
  std::memcpy(data, staging.mapped_, bytes);
}

void Buffer::fill_zero() {
  if (mapped_) {
    owner_->wait();
    std::memset(mapped_, 0, size_);
    return;
  }
  owner_->submit_and_wait([&](VkCommandBuffer cmd) { record_fill_zero(cmd); });
}

void Buffer::record_fill_zero(VkCommandBuffer cmd) {
  before_transfer(cmd);
  vkCmdFillBuffer(cmd, buffer_, 0, VK_WHOLE_SIZE, 0);
  after_transfer(cmd);
}

}  // namespace gi::gpu
