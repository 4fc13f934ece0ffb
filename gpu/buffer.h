// A VkBuffer with its own memory. Where that memory lives is the device's
// choice (Device::staged_buffers): on lavapipe, whose only memory type is
// DEVICE_LOCAL|HOST_VISIBLE|HOST_COHERENT, buffers are mapped and the CPU
// reads and writes them in place; on a discrete GPU they are device-local and
// upload/download/fill_zero go through a host-cached staging buffer with a
// copy on the queue (each a submit-and-wait: call them between frames, never
// while recording). Either way the bytes are the same. A transfer while a
// submission is in flight (Device::submit) first waits for it.
#pragma once
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gi::gpu {

class Device;

enum class BufferMemory {
  device,      // what the GPU reads and writes: device-local where the device stages
  host_write,  // written by the CPU every frame, read by the GPU (frame constants): always mapped
  staging,     // the device's staging buffer: mapped, host-cached where the device has it
};

class Buffer {
 public:
  Buffer() = default;
  // size 0 is rounded up to 16 bytes (Vulkan forbids empty buffers).
  // VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT in usage also allocates the memory
  // with the device-address flag and fills device_address().
  Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, std::string name = {},
         BufferMemory memory = BufferMemory::device);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }
  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  VkDeviceAddress device_address() const { return address_; }
  bool staged() const { return mapped_ == nullptr; }
  const std::string& name() const { return name_; }

  // Bytes at offset (checked against size()).
  void upload_bytes(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void download_bytes(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  void fill_zero();
  // Records the zeroing into cmd, ordered after earlier commands' writes and
  // before later commands' accesses: for buffers cleared within a frame.
  void record_fill_zero(VkCommandBuffer cmd);

  template <class T>
  void upload(std::span<const T> data, VkDeviceSize offset = 0) {
    upload_bytes(data.data(), data.size_bytes(), offset);
  }
  template <class T>
  void upload(const std::vector<T>& data, VkDeviceSize offset = 0) {
    upload(std::span<const T>(data), offset);
  }
  // Elements [first, first + count) as T.
  template <class T>
  std::vector<T> download(std::size_t count, std::size_t first = 0) const {
    std::vector<T> out(count);
    download_bytes(out.data(), count * sizeof(T), first * sizeof(T));
    return out;
  }

 private:
  void destroy() noexcept;

  Device* owner_ = nullptr;  // for staged transfers
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  VkDeviceAddress address_ = 0;
  void* mapped_ = nullptr;
  std::string name_;
};

}  // namespace gi::gpu
