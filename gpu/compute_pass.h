// A compute pipeline with its descriptor set (set 0) and push constants: the
// plumbing every pass driver in gpu/passes/ shares. Bindings are written
// immediately (vkUpdateDescriptorSets), so bind only while the pass is idle
// (every Renderer submission waits, so between frames is always safe).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace gi::gpu {

class Buffer;
class Device;
class ShaderPrewarm;

struct DescriptorBinding {
  std::uint32_t binding;
  VkDescriptorType type;
};

// What scene_bindings.glsl declares (bindings 0-6 of gpu/shaders/bindings.h).
// On a Device of the bvh backend, ComputePass replaces the TLAS binding with
// the BVH's node and triangle buffers, so passes list the same bindings for
// either backend.
std::vector<DescriptorBinding> scene_descriptor_bindings();

// The resources behind those bindings.
struct SceneResources {
  VkAccelerationStructureKHR tlas = VK_NULL_HANDLE;  // rayquery backend
  const Buffer* vertices = nullptr;
  const Buffer* indices = nullptr;
  const Buffer* instances = nullptr;
  const Buffer* materials = nullptr;
  const Buffer* lights = nullptr;
  const Buffer* frame = nullptr;  // uniform FrameConstants
  // bvh backend (gpu/bvh_buffers.h), in place of tlas; last so that
  // positional initialisers of the fields above stay valid.
  const Buffer* bvh_nodes = nullptr;
  const Buffer* bvh_triangles = nullptr;
  const Buffer* dfg_lut = nullptr;  // make_dfg_lut_buffer: BRDF_LAYERED's table
  // Last frame's scene (BINDING_PREVIOUS_SCENE), where the renderer keeps it:
  // its TLAS (rayquery) or BVH node array (bvh).
  VkAccelerationStructureKHR previous_tlas = VK_NULL_HANDLE;
  const Buffer* previous_bvh_nodes = nullptr;
  // Material textures (gpu/scene_texture_buffers.h): placeholders when the
  // scene has none.
  const Buffer* vertex_attributes = nullptr;
  const Buffer* material_textures = nullptr;
  const Buffer* texture_images = nullptr;
  const Buffer* texels = nullptr;
};

// The binding of last frame's scene (a pass that traces it lists it; on a
// bvh Device ComputePass makes it the node buffer's).
DescriptorBinding previous_scene_descriptor_binding();

// The DFG table (core/shared/dfg_lut.h) as the storage buffer SceneResources binds.
Buffer make_dfg_lut_buffer(Device& device);

class ComputePass {
 public:
  ComputePass(Device& device, std::string name, std::span<const std::uint32_t> spirv,
              std::vector<DescriptorBinding> bindings, std::uint32_t push_constant_bytes = 0);
  ~ComputePass();
  ComputePass(ComputePass&& other) noexcept;
  ComputePass& operator=(ComputePass&& other) noexcept;
  ComputePass(const ComputePass&) = delete;
  ComputePass& operator=(const ComputePass&) = delete;

  const std::string& name() const { return name_; }

  void bind_buffer(std::uint32_t binding, const Buffer& buffer);
  void bind_acceleration_structure(std::uint32_t binding, VkAccelerationStructureKHR as);
  void bind_scene(const SceneResources& scene);
  // BINDING_PREVIOUS_SCENE from `scene` (the pass must list it).
  void bind_previous_scene(const SceneResources& scene);

  // Binds pipeline and set, pushes `push` (push_constant_bytes of it), dispatches.
  void dispatch(VkCommandBuffer cmd, std::uint32_t groups_x, std::uint32_t groups_y, std::uint32_t groups_z = 1,
                const void* push = nullptr) const;
  // The same with the group counts read on the device from `args` at `offset`
  // (a VkDispatchIndirectCommand; `args` needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT).
  void dispatch_indirect(VkCommandBuffer cmd, const Buffer& args, VkDeviceSize offset,
                         const void* push = nullptr) const;

 private:
  void destroy() noexcept;
  VkDescriptorType type_of(std::uint32_t binding) const;

  VkDevice device_ = VK_NULL_HANDLE;
  // The device's compiles ahead (null where none): a dispatch waits for them,
  // so that the driver finds this pipeline's code compiled.
  ShaderPrewarm* prewarm_ = nullptr;
  std::string name_;
  std::vector<DescriptorBinding> bindings_;
  std::uint32_t push_bytes_ = 0;
  // Shared with every pass of the device that has the same SPIR-V, bindings
  // and push constants (gpu/pipeline_cache.h); the descriptor set is this pass's.
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

// Makes compute-shader writes visible to later compute-shader reads and host reads.
void compute_barrier(VkCommandBuffer cmd);

// Workgroups needed to cover `n` items with groups of `size`.
inline std::uint32_t group_count(std::uint32_t n, std::uint32_t size) { return (n + size - 1) / size; }

}  // namespace gi::gpu
