#include "gpu/buffer.h"

#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "gpu/device.h"

namespace gi::gpu {

namespace {

std::uint32_t pick_memory_type(VkPhysicalDevice pd, std::uint32_t allowed, const std::string& name) {
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(pd, &mp);
  const VkMemoryPropertyFlags preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT |
                                          VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                          VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  const VkMemoryPropertyFlags fallback = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  for (VkMemoryPropertyFlags want : {preferred, fallback})
    for (std::uint32_t i = 0; i < mp.memoryTypeCount; ++i)
      if ((allowed & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) return i;
  throw DeviceError(fmt::format("Vulkan: no host-visible coherent memory type for buffer '{}'", name));
}

}  // namespace

Buffer::Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, std::string name)
    : device_(device.handle()), size_(size == 0 ? 16 : size), name_(std::move(name)) {
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = size_;
  bci.usage = usage;
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
    mai.memoryTypeIndex = pick_memory_type(device.physical_device(), req.memoryTypeBits, name_);
    check_vk(vkAllocateMemory(device_, &mai, nullptr, &memory_), "vkAllocateMemory");
    check_vk(vkBindBufferMemory(device_, buffer_, memory_, 0), "vkBindBufferMemory");
    check_vk(vkMapMemory(device_, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
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
  if (bytes) std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
}

void Buffer::download_bytes(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (offset + bytes > size_)
    throw DeviceError(fmt::format("buffer '{}': download of {} bytes at {} exceeds its {} bytes", name_, bytes,
                                  offset, size_));
  if (bytes) std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
}

void Buffer::fill_zero() { std::memset(mapped_, 0, size_); }

}  // namespace gi::gpu
