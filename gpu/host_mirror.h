// The host's copy of a small buffer the GPU writes every frame (frame
// measures, hash sums, GI and cache statistics and counters). Where the
// device stages (gpu/buffer.h) the buffer stays device-local, where its
// atomics are fast, and the copy into a mapped, host-cached twin is recorded
// at the end of the frame's own command buffer: reading it afterwards is a
// memcpy, with no submission of its own. On a mapped device (lavapipe) the
// buffer itself is read in place and nothing is recorded.
#pragma once
#include <optional>
#include <vector>

#include "gpu/buffer.h"

namespace gi::gpu {

class HostMirror {
 public:
  // `source` must outlive the mirror and keep its size (make a new mirror
  // for a reallocated buffer).
  HostMirror(Device& device, const Buffer& source);

  // Records the copy, after every earlier command's writes and before host reads.
  void record_copy(VkCommandBuffer cmd) const;
  // Elements [first, first + count) as the last recorded copy left them.
  template <class T>
  std::vector<T> read(std::size_t count, std::size_t first = 0) const {
    return (host_ ? *host_ : *source_).download<T>(count, first);
  }

 private:
  const Buffer* source_;
  std::optional<Buffer> host_;  // staged devices only
};

}  // namespace gi::gpu
