// The `rayquery` backend's acceleration structures (DESIGN §4): one BLAS per
// mesh, built once from the global vertex/index buffers (triangles arrive
// Morton-sorted from core, which lavapipe's BLAS builder needs; a mesh added
// later by a spawn gets its own, the others are kept), and one TLAS
// over the visible instances, rebuilt only when a transform or the visibility
// changed.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/scene_flatten.h"
#include "gpu/buffer.h"

namespace gi::gpu {

class Device;

// An acceleration structure and the buffer that stores it.
struct AccelerationStructure {
  Buffer storage;
  VkAccelerationStructureKHR handle = VK_NULL_HANDLE;
  VkDeviceAddress address = 0;
};

class AccelerationStructures {
 public:
  // vertices/indices: the global buffers of `geometry` (created with
  // geometry_buffer_usage()); BLASes are built here, once.
  AccelerationStructures(Device& device, const FlatGeometry& geometry, const Buffer& vertices, const Buffer& indices);
  ~AccelerationStructures();
  AccelerationStructures(const AccelerationStructures&) = delete;
  AccelerationStructures& operator=(const AccelerationStructures&) = delete;

  // Builds the BLASes of the meshes appended to `geometry` since construction
  // (or the last call); vertices/indices are its (possibly reallocated) global
  // buffers. Earlier meshes must be unchanged (scenario events only append);
  // their BLASes are kept. The next update() rebuilds the TLAS.
  void add_meshes(const FlatGeometry& geometry, const Buffer& vertices, const Buffer& indices);

  // Usage flags the global vertex and index buffers need.
  static VkBufferUsageFlags geometry_buffer_usage();

  // visible[i] says whether instances[i] is drawn (a missing entry = visible).
  // Rebuilds the TLAS only if the visible set or one of its transforms changed
  // (or on the first call). Returns true if it rebuilt.
  bool update(const std::vector<GpuInstance>& instances, const std::vector<bool>& visible);

  VkAccelerationStructureKHR tlas() const { return tlas_.handle; }
  std::uint32_t tlas_builds() const { return tlas_builds_; }
  std::uint32_t tlas_instance_count() const { return tlas_instance_count_; }
  // True once after the TLAS handle changed (it grew): descriptors must be rewritten.
  bool take_tlas_handle_changed() { return std::exchange(tlas_handle_changed_, false); }

 private:
  void destroy(AccelerationStructure& as) noexcept;
  AccelerationStructure create(VkAccelerationStructureTypeKHR type, VkDeviceSize size, const char* name);
  void build_blases(const FlatGeometry& geometry, const Buffer& vertices, const Buffer& indices);
  void build_tlas(const std::vector<VkAccelerationStructureInstanceKHR>& records);

  Device& device_;
  std::vector<AccelerationStructure> blas_;   // one per mesh; handle null for meshes with no triangles
  std::vector<MeshRange> meshes_;
  AccelerationStructure tlas_;
  std::uint32_t tlas_capacity_ = 0;           // instance records the TLAS storage was sized for
  Buffer tlas_instances_;                     // VkAccelerationStructureInstanceKHR[]
  Buffer tlas_scratch_;
  std::uint32_t tlas_builds_ = 0;
  std::uint32_t tlas_instance_count_ = 0;
  bool tlas_handle_changed_ = false;
  bool built_once_ = false;
  std::vector<VkAccelerationStructureInstanceKHR> last_records_;  // of the last build
};

}  // namespace gi::gpu
