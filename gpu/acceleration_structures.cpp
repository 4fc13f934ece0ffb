#include "gpu/acceleration_structures.h"

#include <cstring>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "gpu/device.h"

namespace gi::gpu {

namespace {

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return (v + a - 1) / a * a; }

constexpr VkBufferUsageFlags kStorageUsage =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
constexpr VkBufferUsageFlags kScratchUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
constexpr VkBufferUsageFlags kInputUsage =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;

void build_barrier(VkCommandBuffer cmd) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  b.dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                       1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace

VkBufferUsageFlags AccelerationStructures::geometry_buffer_usage() {
  return VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | kInputUsage;
}

AccelerationStructure AccelerationStructures::create(VkAccelerationStructureTypeKHR type, VkDeviceSize size,
                                                     const char* name) {
  AccelerationStructure as;
  as.storage = Buffer(device_, size, kStorageUsage, name);
  VkAccelerationStructureCreateInfoKHR ci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  ci.buffer = as.storage.handle();
  ci.size = size;
  ci.type = type;
  check_vk(device_.khr().create_acceleration_structure(device_.handle(), &ci, nullptr, &as.handle),
           "vkCreateAccelerationStructureKHR");
  VkAccelerationStructureDeviceAddressInfoKHR ai{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  ai.accelerationStructure = as.handle;
  as.address = device_.khr().get_acceleration_structure_device_address(device_.handle(), &ai);
  return as;
}

void AccelerationStructures::destroy(AccelerationStructure& as) noexcept {
  if (as.handle) device_.khr().destroy_acceleration_structure(device_.handle(), as.handle, nullptr);
  as.handle = VK_NULL_HANDLE;
  as.storage = Buffer();
}

AccelerationStructures::AccelerationStructures(Device& device, const FlatGeometry& geometry, const Buffer& vertices,
                                               const Buffer& indices)
    : device_(device), meshes_(geometry.meshes) {
  build_blases(geometry, vertices, indices);
}

void AccelerationStructures::add_meshes(const FlatGeometry& geometry, const Buffer& vertices, const Buffer& indices) {
  for (std::size_t m = 0; m < meshes_.size(); ++m)
    if (m >= geometry.meshes.size() || meshes_[m] != geometry.meshes[m])
      throw DeviceError(fmt::format("AccelerationStructures::add_meshes: mesh {} changed; meshes may only be appended", m));
  meshes_ = geometry.meshes;
  build_blases(geometry, vertices, indices);
  force_rebuild_ = true;  // the next update() rebuilds the TLAS
}

// Builds the BLAS of every mesh that has none yet (blas_ shorter than meshes_).
void AccelerationStructures::build_blases(const FlatGeometry& geometry, const Buffer& vertices, const Buffer& indices) {
  const std::size_t first = blas_.size(), n = geometry.meshes.size();
  blas_.resize(n);
  std::vector<VkAccelerationStructureGeometryKHR> geoms(n);
  std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos;
  std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
  std::vector<VkDeviceSize> scratch_offsets;
  VkDeviceSize scratch_total = 0;
  Device& device = device_;
  const VkDeviceSize scratch_align = device.min_scratch_offset_alignment();

  try {
    for (std::size_t m = first; m < n; ++m) {
      const MeshRange& r = geometry.meshes[m];
      if (r.triangle_count == 0) continue;  // no BLAS; instances of it are left out of the TLAS
      VkAccelerationStructureGeometryKHR& g = geoms[m];
      g = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
      g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
      g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
      auto& t = g.geometry.triangles;
      t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
      t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;  // GpuVertex::position.xyz at offset 0
      // The mesh's ranges are applied through the addresses, not through
      // primitiveOffset/firstVertex: lavapipe (Mesa 25.0) built wrong
      // geometry for every mesh but the first with those (the walls missed).
      t.vertexData.deviceAddress = vertices.device_address() + VkDeviceSize(r.first_vertex) * sizeof(GpuVertex);
      t.vertexStride = sizeof(GpuVertex);
      t.maxVertex = r.vertex_count > 0 ? r.vertex_count - 1 : 0;
      t.indexType = VK_INDEX_TYPE_UINT32;
      t.indexData.deviceAddress = indices.device_address() + VkDeviceSize(r.first_index) * sizeof(std::uint32_t);

      VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
      info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
      info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
      info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
      info.geometryCount = 1;
      info.pGeometries = &g;
      VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
      device.khr().get_acceleration_structure_build_sizes(
          device.handle(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &r.triangle_count, &sizes);
      blas_[m] = create(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, sizes.accelerationStructureSize,
                        "blas");
      info.dstAccelerationStructure = blas_[m].handle;
      infos.push_back(info);
      scratch_offsets.push_back(scratch_total);
      scratch_total += align_up(sizes.buildScratchSize, scratch_align);

      VkAccelerationStructureBuildRangeInfoKHR range{};
      range.primitiveCount = r.triangle_count;
      range.primitiveOffset = 0;
      range.firstVertex = 0;
      ranges.push_back(range);
    }
    if (!infos.empty()) {
      Buffer scratch(device, scratch_total + scratch_align, kScratchUsage, "blas scratch");
      const VkDeviceAddress base = align_up(scratch.device_address(), scratch_align);
      std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> range_ptrs;
      for (std::size_t i = 0; i < infos.size(); ++i) {
        infos[i].scratchData.deviceAddress = base + scratch_offsets[i];
        range_ptrs.push_back(&ranges[i]);
      }
      device.submit_and_wait([&](VkCommandBuffer cmd) {
        device.khr().cmd_build_acceleration_structures(cmd, std::uint32_t(infos.size()), infos.data(),
                                                       range_ptrs.data());
        build_barrier(cmd);
      });
    }
  } catch (...) {
    for (std::size_t m = first; m < n; ++m) destroy(blas_[m]);
    blas_.resize(first);
    throw;
  }
  spdlog::debug("built {} BLAS", infos.size());
}

AccelerationStructures::~AccelerationStructures() {
  vkDeviceWaitIdle(device_.handle());
  destroy(current_.as);
  destroy(previous_.as);
  for (auto& b : blas_) destroy(b);
}

bool AccelerationStructures::update(const std::vector<GpuInstance>& instances, const std::vector<bool>& visible) {
  // The instance records are a pure function of transforms, visibility and
  // meshes; comparing them with the last build's says whether anything changed.
  std::vector<VkAccelerationStructureInstanceKHR> records;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    if (i < visible.size() && !visible[i]) continue;
    const GpuInstance& inst = instances[i];
    if (inst.triangle_count == 0) continue;
    std::size_t mesh = meshes_.size();
    for (std::size_t m = 0; m < meshes_.size(); ++m)
      if (meshes_[m].triangle_count > 0 && meshes_[m].first_index == inst.first_index) mesh = m;
    if (mesh == meshes_.size())
      throw DeviceError(fmt::format("instance {}: first_index {} matches no mesh", i, inst.first_index));
    VkAccelerationStructureInstanceKHR rec{};
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) rec.transform.matrix[r][c] = inst.object_to_world[c][r];  // glm is column-major
    rec.instanceCustomIndex = std::uint32_t(i);  // the instance's index in FlatInstances
    rec.mask = 0xFF;
    rec.instanceShaderBindingTableRecordOffset = 0;
    rec.flags = VK_GEOMETRY_INSTANCE_FORCE_OPAQUE_BIT_KHR | VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
    rec.accelerationStructureReference = blas_[mesh].address;
    records.push_back(rec);
  }

  const bool rebuilt = force_rebuild_ || !current_.holds(records);
  force_rebuild_ = false;
  if (rebuilt) {
    build_tlas(current_, std::move(records));
    tlas_instance_count_ = std::uint32_t(current_.records.size());
    ++tlas_builds_;
  }
  if (keep_previous_ && !previous_.built) build_tlas(previous_, current_.records);  // the first frame's
  return rebuilt;
}

void AccelerationStructures::end_frame() {
  if (keep_previous_ && current_.built && !previous_.holds(current_.records)) build_tlas(previous_, current_.records);
}

bool AccelerationStructures::TopLevel::holds(const std::vector<VkAccelerationStructureInstanceKHR>& r) const {
  return built && r.size() == records.size() &&
         (r.empty() || std::memcmp(r.data(), records.data(), r.size() * sizeof(r[0])) == 0);
}

void AccelerationStructures::build_tlas(TopLevel& top, std::vector<VkAccelerationStructureInstanceKHR> records) {
  const std::uint32_t count = std::uint32_t(records.size());
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
  g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  g.geometry.instances.arrayOfPointers = VK_FALSE;
  VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  info.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  info.geometryCount = 1;
  info.pGeometries = &g;

  // (Re)allocate when the instance count outgrows the storage; the handle
  // then changes and descriptors must be rewritten.
  if (!top.as.handle || count > top.capacity) {
    vkDeviceWaitIdle(device_.handle());
    destroy(top.as);
    top.capacity = std::max<std::uint32_t>(count, std::max<std::uint32_t>(2 * top.capacity, 16));
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    device_.khr().get_acceleration_structure_build_sizes(
        device_.handle(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &top.capacity, &sizes);
    top.as = create(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, sizes.accelerationStructureSize,
                    &top == &previous_ ? "previous tlas" : "tlas");
    const VkDeviceSize align = device_.min_scratch_offset_alignment();
    top.scratch = Buffer(device_, sizes.buildScratchSize + align, kScratchUsage, "tlas scratch");
    top.instances = Buffer(device_, VkDeviceSize(top.capacity) * sizeof(VkAccelerationStructureInstanceKHR),
                           kInputUsage, "tlas instances");
    tlas_handle_changed_ = true;
  }
  top.instances.upload(records);
  g.geometry.instances.data.deviceAddress = top.instances.device_address();
  info.dstAccelerationStructure = top.as.handle;
  info.scratchData.deviceAddress = align_up(top.scratch.device_address(), device_.min_scratch_offset_alignment());
  VkAccelerationStructureBuildRangeInfoKHR range{};
  range.primitiveCount = count;
  const VkAccelerationStructureBuildRangeInfoKHR* range_ptr = &range;
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    device_.khr().cmd_build_acceleration_structures(cmd, 1, &info, &range_ptr);
    build_barrier(cmd);
  });
  top.records = std::move(records);
  top.built = true;
}

}  // namespace gi::gpu
