// The `rayquery` backend's acceleration structures (docs/design.md §4): one BLAS per
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

  // From now on a second TLAS holds the previous frame's scene (on the first
  // frame, the current one): DI's temporal MIS visibility
  // (restir_di.temporal_mis_scene previous_frame, Bevy #25046). update() may
  // change the current TLAS only; end_frame(), after each rendered frame,
  // makes the previous one what the current one is (a build only when they differ).
  void keep_previous_tlas() { keep_previous_ = true; }
  void end_frame();
  VkAccelerationStructureKHR tlas() const { return current_.as.handle; }
  VkAccelerationStructureKHR previous_tlas() const { return previous_.as.handle; }
  std::uint32_t tlas_builds() const { return tlas_builds_; }
  std::uint32_t tlas_instance_count() const { return tlas_instance_count_; }
  // True once after a TLAS handle changed (it grew): descriptors must be rewritten.
  bool take_tlas_handle_changed() { return std::exchange(tlas_handle_changed_, false); }

 private:
  // A TLAS with the storage it is built in and the records of its last build.
  struct TopLevel {
    AccelerationStructure as;
    std::uint32_t capacity = 0;  // instance records the storage was sized for
    Buffer instances;            // VkAccelerationStructureInstanceKHR[]
    Buffer scratch;
    std::vector<VkAccelerationStructureInstanceKHR> records;
    bool built = false;
    bool holds(const std::vector<VkAccelerationStructureInstanceKHR>& r) const;
  };

  void destroy(AccelerationStructure& as) noexcept;
  AccelerationStructure create(VkAccelerationStructureTypeKHR type, VkDeviceSize size, const char* name);
  void build_blases(const FlatGeometry& geometry, const Buffer& vertices, const Buffer& indices);
  void build_tlas(TopLevel& top, std::vector<VkAccelerationStructureInstanceKHR> records);

  Device& device_;
  std::vector<AccelerationStructure> blas_;   // one per mesh; handle null for meshes with no triangles
  std::vector<MeshRange> meshes_;
  TopLevel current_, previous_;
  bool keep_previous_ = false;
  bool force_rebuild_ = false;  // meshes were added
  std::uint32_t tlas_builds_ = 0;             // of the current TLAS
  std::uint32_t tlas_instance_count_ = 0;
  bool tlas_handle_changed_ = false;
};

}  // namespace gi::gpu
