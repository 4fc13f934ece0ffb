// The base of the ReSTIR family's passes (DI's two dispatches, GI's two and
// specular GI): one invocation per pixel and chain, the scene's bindings, and
// the pass's own buffers stated once, as slots: a binding number (of
// gpu/shaders/di_bindings.h or gi_bindings.h) and the member of the family's
// buffer struct (DiBuffers, GiBuffers) that fills it. The descriptor layout
// and bind() both come from that one list, so a binding cannot be declared
// without being bound, or bound to another buffer than the one it names.
// Bindings only some variants have (the previous scene, the world cache,
// counters) are the family's: `extra` in the layout, bound by the subclass.
#pragma once
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gpu/compute_pass.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

template <class Buffers, class Push>
class ReservoirPass {
 public:
  struct Slot {
    std::uint32_t binding;
    const Buffer* Buffers::*buffer;
  };

  ReservoirPass(Device& device, const char* name, std::span<const std::uint32_t> spirv, std::vector<Slot> slots,
                const std::vector<DescriptorBinding>& extra, std::uint32_t chains)
      : name_(name), slots_(std::move(slots)), chains_(chains),
        pass_(device, name, spirv, layout(slots_, extra), sizeof(Push)) {}

  void record(VkCommandBuffer cmd, std::uint32_t width, std::uint32_t height, const Push& push) const {
    pass_.dispatch(cmd, group_count(width, shader::RAY_WORKGROUP_X), group_count(height, shader::RAY_WORKGROUP_Y),
                   chains_, &push);
  }

 protected:
  // The scene and every slot; a slot whose buffer is missing is a programming error.
  void bind_slots(const SceneResources& scene, const Buffers& b) {
    pass_.bind_scene(scene);
    for (const Slot& s : slots_) {
      const Buffer* buffer = b.*(s.buffer);
      if (!buffer) throw std::logic_error(name_ + ": no buffer for binding " + std::to_string(s.binding));
      pass_.bind_buffer(s.binding, *buffer);
    }
  }
  ComputePass& pass() { return pass_; }

 private:
  static std::vector<DescriptorBinding> layout(const std::vector<Slot>& slots,
                                               const std::vector<DescriptorBinding>& extra) {
    std::vector<DescriptorBinding> b = scene_descriptor_bindings();
    for (const Slot& s : slots) b.push_back({s.binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
    b.insert(b.end(), extra.begin(), extra.end());
    return b;
  }

  std::string name_;
  std::vector<Slot> slots_;
  std::uint32_t chains_;
  ComputePass pass_;
};

}  // namespace gi::gpu
