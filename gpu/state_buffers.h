// The pipeline's persistent GPU state, named: every buffer whose contents
// carry from one frame to the next (reservoirs, last frame's surfaces, world
// cache cells, accumulation sums). Captures write them, replay restores them,
// and the determinism check hashes them (docs/design.md §6, §9). A pass driver that
// owns such a buffer lists it through `list_state`; the Renderer gathers them.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "gpu/buffer.h"

namespace gi::gpu {

struct StateBuffer {
  std::string name;   // unique and stable, e.g. "world_cache/life", "di/stored_reservoirs"
  Buffer* buffer = nullptr;
  // numpy dtype string of one element ("<u4", "<f4", "<i4", "<u8") and the
  // shape in elements; product(shape) · itemsize ≤ buffer->size().
  std::string dtype;
  std::vector<std::uint64_t> shape;
  // What one innermost row is when it is a struct, e.g. "DiReservoir (core/shared/reservoir.h)".
  std::string layout;
};

using StateList = std::vector<StateBuffer>;

// Host-side state a pass carries from one frame to the next (last frame's
// light identities, whether there is a history yet), as named 32-bit words:
// captures save it, replay restores it next to the buffers.
struct HostStateEntry {
  std::string name;  // e.g. "di/previous_light_keys"
  std::vector<std::uint32_t> words;
};

using HostState = std::vector<HostStateEntry>;

// The entry called `name`, or nullptr.
inline const HostStateEntry* find_host_state(const HostState& state, const std::string& name) {
  for (const HostStateEntry& e : state)
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace gi::gpu
