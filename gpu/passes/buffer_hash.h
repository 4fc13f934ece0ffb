// The harness's buffer hash on the GPU (gpu/shaders/buffer_hash.comp,
// core/shared/word_hash.h): the per-frame image hashes, the state hashes of
// the determinism check and replay's hash log, without reading the buffers
// back. word_hash_bytes over the same bytes on the CPU gives the same
// 16 hex digits (a capture's manifest uses it; tests/frame_output_test.cpp).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/host_mirror.h"

namespace gi::gpu {

class ShaderCompiler;

// One buffer's bytes [offset, offset + bytes) to hash (bytes a multiple of 4).
struct HashRange {
  const Buffer* buffer = nullptr;
  VkDeviceSize bytes = 0;
  VkDeviceSize offset = 0;
};

class BufferHash {
 public:
  static constexpr const char* kShader = "gpu/shaders/buffer_hash.comp";

  // Results for `slots` ranges per submission (grown by hash_now as needed).
  BufferHash(Device& device, ShaderCompiler& compiler, std::uint32_t slots = 1);

  // Recording: zero every slot, then hash ranges into slots (each after the
  // commands that wrote it: put a compute barrier between), then the copy
  // of the sums for the host.
  void record_clear(VkCommandBuffer cmd);
  void record(VkCommandBuffer cmd, const HashRange& range, std::uint32_t slot);
  void record_to_host(VkCommandBuffer cmd) const { sums_host_->record_copy(cmd); }
  // After the submission: the slot's hash, 16 hex digits; the first `count` slots' (one read).
  std::string result(std::uint32_t slot) const;
  std::vector<std::string> results(std::uint32_t count) const;

  // Hashes the ranges in one submission of its own (between frames).
  std::vector<std::string> hash_now(const std::vector<HashRange>& ranges);
  // Records clear, hashes of ranges[i] into slot i, and the copy for the host
  // (call ensure_slots(ranges.size()) before recording).
  void record_all(VkCommandBuffer cmd, const std::vector<HashRange>& ranges);
  // At least `slots` slots (reallocates and rebinds: not while recording).
  void ensure_slots(std::uint32_t slots);

 private:
  std::string finished(glm::uvec2 sums, std::uint32_t slot) const;

  Device& device_;
  ComputePass pass_;
  Buffer sums_;                        // uvec2 per slot
  std::optional<HostMirror> sums_host_;
  std::vector<std::uint32_t> words_;  // per slot: the words its last record hashed
};

}  // namespace gi::gpu
