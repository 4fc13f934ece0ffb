#include "gpu/compute_pass.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "core/shared/dfg_lut.h"
#include "gpu/buffer.h"
#include "gpu/device.h"
#include "gpu/pipeline_cache.h"
#include "gpu/shader_prewarm.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

// GIHARNESS_TEST_SLOW_PASS=<pass>:<factor> (factor > 1): that pass's every
// dispatch does `factor` times its work, a real slowdown for the tests of
// the nightly's timing verdicts (reports/timing_verdict.h). The work is the
// same dispatch again, after a barrier, and a fraction of its workgroups
// for the rest: for a pass that only writes what it reads from elsewhere
// (light_tiles) the results are unchanged; one that reads its own output
// (a temporal pass, the cache's decay) computes other results.
struct TestSlowdown {
  std::string pass;
  double factor = 1.0;
};

const TestSlowdown& test_slowdown() {
  static const TestSlowdown slowdown = [] {
    TestSlowdown s;
    const char* env = std::getenv("GIHARNESS_TEST_SLOW_PASS");
    const std::string text = env ? env : "";
    if (text.empty()) return s;
    const std::size_t colon = text.rfind(':');
    char* end = nullptr;
    const double factor = colon == std::string::npos ? 0.0 : std::strtod(text.c_str() + colon + 1, &end);
    if (colon == 0 || colon == std::string::npos || end == text.c_str() + colon + 1 || *end != '\0' ||
        !(factor >= 1.0 && factor <= 16.0))
      throw InputError("GIHARNESS_TEST_SLOW_PASS", "",
                       fmt::format("<pass>:<factor> with 1 <= factor <= 16, got \"{}\"", text));
    s.pass = text.substr(0, colon);
    s.factor = factor;
    spdlog::warn("GIHARNESS_TEST_SLOW_PASS: every dispatch of {} does {}x its work", s.pass, s.factor);
    return s;
  }();
  return slowdown;
}

// The extra work of a slowed pass: whole repeats, then the fraction as a
// share of the largest grid dimension.
void record_slowdown(VkCommandBuffer cmd, double factor, std::uint32_t gx, std::uint32_t gy, std::uint32_t gz) {
  double extra = factor - 1.0;
  for (; extra >= 1.0 - 1e-9; extra -= 1.0) {
    compute_barrier(cmd);
    vkCmdDispatch(cmd, gx, gy, gz);
  }
  if (extra <= 1e-9) return;
  std::uint32_t* largest = gx >= gy && gx >= gz ? &gx : gy >= gz ? &gy : &gz;
  *largest = std::max(1u, std::uint32_t(std::ceil(extra * double(*largest))));
  compute_barrier(cmd);
  vkCmdDispatch(cmd, gx, gy, gz);
}

}  // namespace

std::vector<DescriptorBinding> scene_descriptor_bindings() {
  return {{BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR},
          {BINDING_VERTICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_INSTANCES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_MATERIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_LIGHTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER},
          {BINDING_DFG_LUT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_VERTEX_ATTRIBUTES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_MATERIAL_TEXTURES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_TEXTURE_IMAGES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
          {BINDING_TEXELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
}

DescriptorBinding previous_scene_descriptor_binding() {
  return {BINDING_PREVIOUS_SCENE, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR};
}

Buffer make_dfg_lut_buffer(Device& device) {
  Buffer b(device, sizeof(DFG_LUT), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "DFG table");
  b.upload(std::span<const std::uint32_t>(DFG_LUT));
  return b;
}

ComputePass::ComputePass(Device& device, std::string name, std::span<const std::uint32_t> spirv,
                         std::vector<DescriptorBinding> bindings, std::uint32_t push_constant_bytes)
    : device_(device.handle()), prewarm_(device.prewarm()), name_(std::move(name)), bindings_(std::move(bindings)),
      push_bytes_(push_constant_bytes) {
  test_slowdown();  // a malformed GIHARNESS_TEST_SLOW_PASS is bad input before any recording
  if (device.backend() == TraceBackend::bvh) {
    const auto tlas = std::find_if(bindings_.begin(), bindings_.end(), [](const DescriptorBinding& b) {
      return b.binding == BINDING_TLAS && b.type == VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
    });
    if (tlas != bindings_.end()) {
      *tlas = {BINDING_BVH_NODES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
      bindings_.push_back({BINDING_BVH_TRIANGLES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
    }
    for (DescriptorBinding& b : bindings_)
      if (b.binding == BINDING_PREVIOUS_SCENE) b.type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  }
  try {
    const SharedPipeline& shared = device.pipelines().get(name_, spirv, bindings_, push_bytes_);
    set_layout_ = shared.set_layout;
    layout_ = shared.layout;
    pipeline_ = shared.pipeline;
    std::map<VkDescriptorType, std::uint32_t> counts;
    for (const auto& b : bindings_) ++counts[b.type];

    std::vector<VkDescriptorPoolSize> sizes;
    for (const auto& [type, n] : counts) sizes.push_back({type, n});
    VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpci.maxSets = 1;
    dpci.poolSizeCount = std::uint32_t(sizes.size());
    dpci.pPoolSizes = sizes.data();
    check_vk(vkCreateDescriptorPool(device_, &dpci, nullptr, &pool_), "vkCreateDescriptorPool");
    VkDescriptorSetAllocateInfo dsai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    dsai.descriptorPool = pool_;
    dsai.descriptorSetCount = 1;
    dsai.pSetLayouts = &set_layout_;
    check_vk(vkAllocateDescriptorSets(device_, &dsai, &set_), "vkAllocateDescriptorSets");
  } catch (...) {
    destroy();
    throw;
  }
}

void ComputePass::destroy() noexcept {
  if (!device_) return;
  // The pipeline and its layouts are the device's (PipelineCache).
  if (pool_) vkDestroyDescriptorPool(device_, pool_, nullptr);
  pool_ = VK_NULL_HANDLE;
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  set_ = VK_NULL_HANDLE;
}

ComputePass::~ComputePass() { destroy(); }

ComputePass::ComputePass(ComputePass&& other) noexcept { *this = std::move(other); }

ComputePass& ComputePass::operator=(ComputePass&& other) noexcept {
  if (this != &other) {
    destroy();
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    prewarm_ = std::exchange(other.prewarm_, nullptr);
    name_ = std::move(other.name_);
    bindings_ = std::move(other.bindings_);
    push_bytes_ = other.push_bytes_;
    set_layout_ = std::exchange(other.set_layout_, VK_NULL_HANDLE);
    layout_ = std::exchange(other.layout_, VK_NULL_HANDLE);
    pipeline_ = std::exchange(other.pipeline_, VK_NULL_HANDLE);
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    set_ = std::exchange(other.set_, VK_NULL_HANDLE);
  }
  return *this;
}

VkDescriptorType ComputePass::type_of(std::uint32_t binding) const {
  for (const auto& b : bindings_)
    if (b.binding == binding) return b.type;
  throw DeviceError(fmt::format("pass '{}' has no binding {}", name_, binding));
}

void ComputePass::bind_buffer(std::uint32_t binding, const Buffer& buffer) {
  VkDescriptorBufferInfo info{buffer.handle(), 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set_;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type_of(binding);
  w.pBufferInfo = &info;
  vkUpdateDescriptorSets(device_, 1, &w, 0, nullptr);
}

void ComputePass::bind_acceleration_structure(std::uint32_t binding, VkAccelerationStructureKHR as) {
  VkWriteDescriptorSetAccelerationStructureKHR asw{
      VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
  asw.accelerationStructureCount = 1;
  asw.pAccelerationStructures = &as;
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.pNext = &asw;
  w.dstSet = set_;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type_of(binding);
  vkUpdateDescriptorSets(device_, 1, &w, 0, nullptr);
}

void ComputePass::bind_scene(const SceneResources& scene) {
  if (type_of(BINDING_TLAS) == VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR) {
    bind_acceleration_structure(BINDING_TLAS, scene.tlas);
  } else {
    if (!scene.bvh_nodes || !scene.bvh_triangles)
      throw DeviceError(fmt::format("pass '{}': a bvh-backend pass bound without BVH buffers", name_));
    bind_buffer(BINDING_BVH_NODES, *scene.bvh_nodes);
    bind_buffer(BINDING_BVH_TRIANGLES, *scene.bvh_triangles);
  }
  bind_buffer(BINDING_VERTICES, *scene.vertices);
  bind_buffer(BINDING_INDICES, *scene.indices);
  bind_buffer(BINDING_INSTANCES, *scene.instances);
  bind_buffer(BINDING_MATERIALS, *scene.materials);
  bind_buffer(BINDING_LIGHTS, *scene.lights);
  bind_buffer(BINDING_FRAME, *scene.frame);
  if (!scene.dfg_lut) throw DeviceError(fmt::format("pass '{}': bound without the DFG table", name_));
  bind_buffer(BINDING_DFG_LUT, *scene.dfg_lut);
  if (!scene.vertex_attributes || !scene.material_textures || !scene.texture_images || !scene.texels)
    throw DeviceError(fmt::format("pass '{}': bound without the material-texture buffers", name_));
  bind_buffer(BINDING_VERTEX_ATTRIBUTES, *scene.vertex_attributes);
  bind_buffer(BINDING_MATERIAL_TEXTURES, *scene.material_textures);
  bind_buffer(BINDING_TEXTURE_IMAGES, *scene.texture_images);
  bind_buffer(BINDING_TEXELS, *scene.texels);
}

void ComputePass::bind_previous_scene(const SceneResources& scene) {
  if (type_of(BINDING_PREVIOUS_SCENE) == VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR) {
    if (!scene.previous_tlas) throw DeviceError(fmt::format("pass '{}': bound without last frame's TLAS", name_));
    bind_acceleration_structure(BINDING_PREVIOUS_SCENE, scene.previous_tlas);
  } else {
    if (!scene.previous_bvh_nodes)
      throw DeviceError(fmt::format("pass '{}': bound without last frame's BVH nodes", name_));
    bind_buffer(BINDING_PREVIOUS_SCENE, *scene.previous_bvh_nodes);
  }
}

void ComputePass::dispatch(VkCommandBuffer cmd, std::uint32_t gx, std::uint32_t gy, std::uint32_t gz,
                           const void* push) const {
  if (prewarm_) prewarm_->drain();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
  if (push_bytes_ && push) vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes_, push);
  vkCmdDispatch(cmd, gx, gy, gz);
  const TestSlowdown& slow = test_slowdown();
  if (slow.factor > 1.0 && slow.pass == name_) record_slowdown(cmd, slow.factor, gx, gy, gz);
}

void ComputePass::dispatch_indirect(VkCommandBuffer cmd, const Buffer& args, VkDeviceSize offset,
                                    const void* push) const {
  if (prewarm_) prewarm_->drain();
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
  if (push_bytes_ && push) vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes_, push);
  vkCmdDispatchIndirect(cmd, args.handle(), offset);
}

void compute_barrier(VkCommandBuffer cmd) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &b, 0, nullptr, 0,
                       nullptr);
}

}  // namespace gi::gpu
