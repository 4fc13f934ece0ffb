// Compute pipelines shared by every pass of one Device that asks for the same
// SPIR-V, bindings and push constants. The chains of a run (each a Renderer
// of its own, RunSetup::chains) and a process's further runs (the
// determinism check's rerun and replay) then create each pipeline once.
// lavapipe takes 10-640 ms to create one even when its disk cache holds the
// code (the SPIR-V's translation and optimisation); gi_cornell_box's 10
// chains spent 12.8 s of a 30 s run there. A VkPipeline is immutable, and
// binding one in many command buffers is what Vulkan intends; each pass keeps
// its own descriptor set. The output is bit-identical: the same SPIR-V makes
// the same code.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gi::gpu {

struct DescriptorBinding;
class ShaderPrewarm;

// A compute pipeline with its layouts (set 0 holds `bindings`).
struct SharedPipeline {
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
};

class PipelineCache {
 public:
  // prewarm: compiles each new pipeline ahead (may be null). timed: creation
  // counts as the "pipelines" phase (not on a prewarm worker's device, whose
  // time the main thread's wait already counts).
  PipelineCache(VkDevice device, ShaderPrewarm* prewarm, bool timed)
      : device_(device), prewarm_(prewarm), timed_(timed) {}
  ~PipelineCache();  // destroys every pipeline: before the device
  PipelineCache(const PipelineCache&) = delete;
  PipelineCache& operator=(const PipelineCache&) = delete;

  // The pipeline of this SPIR-V, set-0 layout and push-constant size, made
  // on first request (`name` names it in errors and the debug log). Valid
  // for the cache's lifetime. DeviceError when the driver refuses it.
  const SharedPipeline& get(const std::string& name, std::span<const std::uint32_t> spirv,
                            const std::vector<DescriptorBinding>& bindings, std::uint32_t push_constant_bytes);
  std::size_t size() const;

 private:
  struct Entry {
    std::vector<std::uint32_t> spirv;
    std::vector<std::pair<std::uint32_t, VkDescriptorType>> bindings;
    std::uint32_t push_bytes = 0;
    std::unique_ptr<SharedPipeline> pipeline;
  };
  SharedPipeline create(const std::string& name, std::span<const std::uint32_t> spirv,
                        const std::vector<DescriptorBinding>& bindings, std::uint32_t push_constant_bytes) const;
  void destroy(const SharedPipeline& p) const noexcept;

  VkDevice device_;
  ShaderPrewarm* prewarm_;
  bool timed_;
  mutable std::mutex mutex_;
  std::multimap<std::uint64_t, Entry> entries_;  // by a hash of the SPIR-V; compared in full
};

}  // namespace gi::gpu
