#include "gpu/pipeline_cache.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <xxhash.h>

#include "core/errors.h"
#include "core/phase_clock.h"
#include "gpu/compute_pass.h"
#include "gpu/device.h"
#include "gpu/shader_prewarm.h"

namespace gi::gpu {

PipelineCache::~PipelineCache() {
  for (const auto& [key, e] : entries_) destroy(*e.pipeline);
}

std::size_t PipelineCache::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

const SharedPipeline& PipelineCache::get(const std::string& name, std::span<const std::uint32_t> spirv,
                                         const std::vector<DescriptorBinding>& bindings,
                                         std::uint32_t push_constant_bytes) {
  std::vector<std::pair<std::uint32_t, VkDescriptorType>> layout;
  for (const DescriptorBinding& b : bindings) layout.emplace_back(b.binding, b.type);
  const std::uint64_t key = XXH3_64bits(spirv.data(), spirv.size_bytes());
  std::lock_guard lock(mutex_);
  const auto [first, last] = entries_.equal_range(key);
  for (auto it = first; it != last; ++it) {
    const Entry& e = it->second;
    if (e.push_bytes == push_constant_bytes && e.bindings == layout &&
        std::equal(e.spirv.begin(), e.spirv.end(), spirv.begin(), spirv.end())) {
      spdlog::debug("pass '{}': pipeline shared", name);
      return *e.pipeline;
    }
  }
  Entry e{{spirv.begin(), spirv.end()}, std::move(layout), push_constant_bytes,
          std::make_unique<SharedPipeline>(create(name, spirv, bindings, push_constant_bytes))};
  if (prewarm_) prewarm_->add(name, spirv, bindings, push_constant_bytes);
  return *entries_.emplace(key, std::move(e))->second.pipeline;
}

SharedPipeline PipelineCache::create(const std::string& name, std::span<const std::uint32_t> spirv,
                                     const std::vector<DescriptorBinding>& bindings,
                                     std::uint32_t push_constant_bytes) const {
  std::optional<PhaseScope> timed;
  if (timed_) timed.emplace(phase::kPipelines);
  SharedPipeline p;
  try {
    VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smci.codeSize = spirv.size_bytes();
    smci.pCode = spirv.data();
    check_vk(vkCreateShaderModule(device_, &smci, nullptr, &p.module), "vkCreateShaderModule");

    std::vector<VkDescriptorSetLayoutBinding> layout_bindings;
    for (const DescriptorBinding& b : bindings) {
      VkDescriptorSetLayoutBinding lb{};
      lb.binding = b.binding;
      lb.descriptorType = b.type;
      lb.descriptorCount = 1;
      lb.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
      layout_bindings.push_back(lb);
    }
    VkDescriptorSetLayoutCreateInfo dslci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dslci.bindingCount = std::uint32_t(layout_bindings.size());
    dslci.pBindings = layout_bindings.data();
    check_vk(vkCreateDescriptorSetLayout(device_, &dslci, nullptr, &p.set_layout), "vkCreateDescriptorSetLayout");

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.setLayoutCount = 1;
    plci.pSetLayouts = &p.set_layout;
    plci.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
    plci.pPushConstantRanges = &range;
    check_vk(vkCreatePipelineLayout(device_, &plci, nullptr, &p.layout), "vkCreatePipelineLayout");

    VkComputePipelineCreateInfo cpci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = p.module;
    cpci.stage.pName = "main";
    cpci.layout = p.layout;
    const auto compile_start = std::chrono::steady_clock::now();
    const VkResult r = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &cpci, nullptr, &p.pipeline);
    // The driver's compile, cached by the driver, not by us. lavapipe defers
    // its LLVM compile to the first dispatch: a variant new to its cache costs
    // there, up to minutes for the GI passes (README "Tests").
    spdlog::debug("pass '{}': pipeline created in {:.0f} ms", name,
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - compile_start).count());
    if (r != VK_SUCCESS)
      throw DeviceError(fmt::format("Vulkan: pass '{}': vkCreateComputePipelines failed: {}", name, vk_result_name(r)));
  } catch (...) {
    destroy(p);
    throw;
  }
  return p;
}

void PipelineCache::destroy(const SharedPipeline& p) const noexcept {
  if (p.pipeline) vkDestroyPipeline(device_, p.pipeline, nullptr);
  if (p.layout) vkDestroyPipelineLayout(device_, p.layout, nullptr);
  if (p.set_layout) vkDestroyDescriptorSetLayout(device_, p.set_layout, nullptr);
  if (p.module) vkDestroyShaderModule(device_, p.module, nullptr);
}

}  // namespace gi::gpu
