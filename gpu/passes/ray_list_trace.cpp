#include "gpu/passes/ray_list_trace.h"

#include <fmt/format.h>

#include "core/errors.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

template <class T>
Buffer make_buffer(Device& device, const std::vector<T>& data, VkBufferUsageFlags usage, const char* name) {
  Buffer b(device, std::max<VkDeviceSize>(data.size() * sizeof(T), 16), usage, name);
  if (!data.empty()) b.upload(data);
  return b;
}

VkBufferUsageFlags geometry_usage(const Device& device) {
  return device.backend() == TraceBackend::rayquery ? AccelerationStructures::geometry_buffer_usage() : kStorage;
}

ComputePass make_pass(Device& device, ShaderCompiler& compiler) {
  compiler.set_global_defines(trace_backend_defines(device));
  std::vector<DescriptorBinding> bindings = scene_descriptor_bindings();
  bindings.push_back({BINDING_TEST_RAYS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  bindings.push_back({BINDING_TEST_RESULTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  return ComputePass(device, "ray_list_trace", compiler.compile_file(RayListTrace::kShader).spirv,
                     std::move(bindings), 2 * sizeof(std::uint32_t));
}

}  // namespace

static_assert(sizeof(TestRay) == 32 && sizeof(TestResult) == 32);

RayListTrace::RayListTrace(Device& device, ShaderCompiler& compiler, const FlatGeometry& geometry,
                           const FlatInstances& flat, const std::vector<bool>& visible)
    : device_(device),
      vertices_(make_buffer(device, geometry.vertices, geometry_usage(device), "vertices")),
      indices_(make_buffer(device, geometry.indices, geometry_usage(device), "indices")),
      instances_(make_buffer(device, flat.instances, kStorage, "instances")),
      materials_(make_buffer(device, flat.materials, kStorage, "materials")),
      lights_(make_buffer(device, flat.lights, kStorage, "lights")),
      frame_(device, sizeof(FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, "frame constants", BufferMemory::host_write),
      dfg_lut_(make_dfg_lut_buffer(device)),
      textures_(device),
      pass_(make_pass(device, compiler)),
      timer_(device) {
  FrameConstants frame{};
  frame.counts = glm::uvec4(std::uint32_t(flat.lights.size()), flat.directional_light_count, 1, 0);
  frame_.upload_bytes(&frame, sizeof frame);
  if (device.backend() == TraceBackend::bvh) {
    bvh_.emplace(device, geometry);
    bvh_->update(flat.instances, visible);
  } else {
    as_.emplace(device, geometry, vertices_, indices_);
    as_->update(flat.instances, visible);
  }
  SceneResources scene{as_ ? as_->tlas() : VK_NULL_HANDLE, &vertices_, &indices_, &instances_, &materials_,
                       &lights_, &frame_};
  scene.dfg_lut = &dfg_lut_;
  textures_.update_geometry(geometry);
  textures_.update_materials(flat);
  textures_.add_to(scene);
  if (bvh_) {
    scene.bvh_nodes = &bvh_->nodes();
    scene.bvh_triangles = &bvh_->triangles();
  }
  pass_.bind_scene(scene);
}

RayListTrace::~RayListTrace() { vkDeviceWaitIdle(device_.handle()); }

std::vector<TestResult> RayListTrace::trace(const std::vector<TestRay>& rays, std::uint32_t mode) {
  if (rays.empty()) return {};
  const VkDeviceSize bytes = rays.size() * sizeof(TestRay);
  if (!rays_ || rays_.size() < bytes) {
    rays_ = Buffer(device_, bytes, kStorage, "test rays");
    results_ = Buffer(device_, rays.size() * sizeof(TestResult), kStorage, "test results");
    pass_.bind_buffer(BINDING_TEST_RAYS, rays_);
    pass_.bind_buffer(BINDING_TEST_RESULTS, results_);
  }
  rays_.upload(rays);
  const std::uint32_t push[2] = {std::uint32_t(rays.size()), mode};
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    timer_.begin_frame(cmd);
    timer_.begin(cmd, "ray_list_trace");
    pass_.dispatch(cmd, group_count(std::uint32_t(rays.size()), TEST_RAY_WORKGROUP), 1, 1, push);
    timer_.end(cmd);
    compute_barrier(cmd);
  });
  timer_.resolve();
  last_ms_ = timer_.timings().empty() ? 0.0 : timer_.timings().front().ms;
  return results_.download<TestResult>(rays.size());
}

}  // namespace gi::gpu
