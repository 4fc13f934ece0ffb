#include "gpu/passes/buffer_hash.h"

#include <fmt/format.h>

#include "core/errors.h"
#include "core/shared/word_hash.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/frame_output_bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

struct HashPush {
  glm::uvec2 address;
  std::uint32_t words, slot;
};

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

// Workgroups along x at most; the rest along y (the shader linearises them).
constexpr std::uint32_t kMaxGroupsX = 65535;

}  // namespace

BufferHash::BufferHash(Device& device, ShaderCompiler& compiler, std::uint32_t slots)
    : device_(device),
      pass_(device, "buffer_hash", compiler.compile_file(kShader).spirv,
            {{BINDING_HASH_SUMS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}}, sizeof(HashPush)) {
  ensure_slots(slots);
}

void BufferHash::ensure_slots(std::uint32_t slots) {
  if (slots <= words_.size()) return;
  sums_host_.reset();
  sums_ = Buffer(device_, slots * sizeof(glm::uvec2), kStorage, "buffer hash sums");
  sums_host_.emplace(device_, sums_);
  words_.assign(slots, 0);
  pass_.bind_buffer(BINDING_HASH_SUMS, sums_);
}

void BufferHash::record_clear(VkCommandBuffer cmd) { sums_.record_fill_zero(cmd); }

void BufferHash::record(VkCommandBuffer cmd, const HashRange& range, std::uint32_t slot) {
  if (slot >= words_.size()) throw DeviceError(fmt::format("BufferHash: slot {} of {}", slot, words_.size()));
  const Buffer& b = *range.buffer;
  if (range.bytes % 4 || range.offset % 4 || range.offset + range.bytes > b.size() || !b.device_address())
    throw DeviceError(fmt::format("BufferHash: buffer '{}' cannot hash {} bytes at {} (size {}, words of 4 bytes)",
                                  b.name(), range.bytes, range.offset, b.size()));
  const std::uint64_t words = range.bytes / 4;
  if (words > 0xFFFFFFFFull) throw DeviceError(fmt::format("BufferHash: buffer '{}' is over 2^32 words", b.name()));
  words_[slot] = static_cast<std::uint32_t>(words);
  if (words == 0) return;
  const VkDeviceAddress at = b.device_address() + range.offset;
  const HashPush push{glm::uvec2(std::uint32_t(at), std::uint32_t(at >> 32)), std::uint32_t(words), slot};
  const std::uint32_t chunks = group_count(std::uint32_t(words), WORD_HASH_CHUNK);
  const std::uint32_t groups = group_count(chunks, BUFFER_HASH_GROUP);
  const std::uint32_t gx = std::min(groups, kMaxGroupsX), gy = group_count(groups, gx);
  // Groups past the last chunk (gx * gy > groups) find no chunk and add nothing.
  pass_.dispatch(cmd, gx, gy, 1, &push);
}

// The slot's 16 hex digits from its lane sums and the words it hashed.
std::string BufferHash::finished(glm::uvec2 sums, std::uint32_t slot) const {
  return word_hash_hex(word_hash_finish(sums, words_.at(slot)));
}

std::string BufferHash::result(std::uint32_t slot) const {
  return finished(sums_host_->read<glm::uvec2>(1, slot)[0], slot);
}

void BufferHash::record_all(VkCommandBuffer cmd, const std::vector<HashRange>& ranges) {
  record_clear(cmd);
  for (std::uint32_t i = 0; i < ranges.size(); ++i) record(cmd, ranges[i], i);
  compute_barrier(cmd);
  record_to_host(cmd);
}

std::vector<std::string> BufferHash::results(std::uint32_t count) const {
  if (count > words_.size()) throw DeviceError(fmt::format("BufferHash: {} results of {} slots", count, words_.size()));
  const std::vector<glm::uvec2> sums = sums_host_->read<glm::uvec2>(count);
  std::vector<std::string> out;
  for (std::uint32_t i = 0; i < count; ++i) out.push_back(finished(sums[i], i));
  return out;
}

std::vector<std::string> BufferHash::hash_now(const std::vector<HashRange>& ranges) {
  ensure_slots(std::uint32_t(ranges.size()));
  device_.submit_and_wait([&](VkCommandBuffer cmd) { record_all(cmd, ranges); });
  return results(std::uint32_t(ranges.size()));
}

}  // namespace gi::gpu
