// A VkBuffer with its own memory, persistently mapped. Every buffer is host
// visible for now (lavapipe's only memory type is DEVICE_LOCAL|HOST_VISIBLE|
// HOST_COHERENT, so this costs nothing there); a discrete GPU would want
// device-local buffers plus staging copies — not done yet.
#pragma once
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gi::gpu {

class Device;

class Buffer {
 public:
  Buffer() = default;
  // size 0 is rounded up to 16 bytes (Vulkan forbids empty buffers).
  // VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT in usage also allocates the memory
  // with the device-address flag and fills device_address().
  Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, std::string name = {});
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }
  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  VkDeviceAddress device_address() const { return address_; }
  void* mapped() const { return mapped_; }
  const std::string& name() const { return name_; }

  // Bytes at offset (checked against size()).
  void upload_bytes(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void download_bytes(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  void fill_zero();

  template <class T>
  void upload(std::span<const T> data, VkDeviceSize offset = 0) {
    upload_bytes(data.data(), data.size_bytes(), offset);
  }
  template <class T>
  void upload(const std::vector<T>& data, VkDeviceSize offset = 0) {
    upload(std::span<const T>(data), offset);
  }
  template <class T>
  std::vector<T> download(std::size_t count) const {
    std::vector<T> out(count);
    download_bytes(out.data(), count * sizeof(T));
    return out;
  }

 private:
  void destroy() noexcept;

  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  VkDeviceAddress address_ = 0;
  void* mapped_ = nullptr;
  std::string name_;
};

}  // namespace gi::gpu
