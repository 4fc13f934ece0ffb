// The Vulkan device: instance, physical-device choice (lavapipe by default,
// docs/design.md §4), one compute queue (with the ray-query extensions only for the
// `rayquery` tracing backend), one command pool and a submit-and-wait helper.
// Everything else in gpu/ borrows it.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vulkan/vulkan.h>

namespace gi::gpu {

class PipelineCache;
class ShaderPrewarm;

// What a Device is for: a run's (main), or a worker's of gpu/shader_prewarm.h,
// which compiles the main device's pipelines ahead and prewarms nothing itself.
enum class DeviceRole { main, shader_prewarm };

// Throws gi::DeviceError naming the call and the VkResult unless result is VK_SUCCESS.
void check_vk(VkResult result, const char* what);
const char* vk_result_name(VkResult result);

// How rays are traced (docs/design.md §4): hardware/driver ray queries over
// VK_KHR_acceleration_structure, or the compute-shader BVH (gpu/bvh_buffers.h,
// gpu/shaders/trace_bvh.glsl), which needs nothing beyond Vulkan 1.2 compute.
enum class TraceBackend { rayquery, bvh };
// --backend: `automatic` picks bvh on lavapipe (2.5-3x faster there, docs/design.md §4)
// and on devices without ray query, rayquery elsewhere.
enum class BackendRequest { automatic, rayquery, bvh };
const char* backend_name(TraceBackend backend);
// "auto", "rayquery" or "bvh"; throws gi::InputError naming --backend otherwise.
BackendRequest parse_backend_request(const std::string& text);

struct DeviceInfo {
  std::string name;            // VkPhysicalDeviceProperties::deviceName
  std::string driver_name;     // e.g. "llvmpipe"
  std::string driver_info;     // e.g. "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"
  std::string mesa_version;    // parsed from driver_info ("25.0.7-2~bpo12+1"), empty if absent
  std::string llvm_version;    // parsed from driver_info ("15.0.6"), empty if absent
  std::string api_version;     // "1.3.296"
  std::uint32_t vendor_id = 0;
  std::uint32_t device_id = 0;
  std::uint32_t subgroup_size = 0;
  std::string lp_num_threads;  // env LP_NUM_THREADS (lavapipe's thread count) or "default"
  double timestamp_period_ns = 0.0;
  int device_index = 0;
  bool ray_query = false;      // the device offers VK_KHR_ray_query + acceleration structures
  // "cpu" (lavapipe), "discrete_gpu", "integrated_gpu", "virtual_gpu" or "other".
  std::string device_type;
  std::string backend;         // the tracing backend this Device was created for
  // Where buffers live (gpu/buffer.h): "staged" (device-local memory, copies
  // through a host-cached staging buffer) or "mapped" (one host-visible
  // memory, the CPU reads and writes it in place).
  std::string buffer_memory;

  nlohmann::json to_json() const;
};

// KHR entry points that the loader does not export (loaded with vkGetDeviceProcAddr).
struct KhrFunctions {
  PFN_vkCreateAccelerationStructureKHR create_acceleration_structure = nullptr;
  PFN_vkDestroyAccelerationStructureKHR destroy_acceleration_structure = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR get_acceleration_structure_build_sizes = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR cmd_build_acceleration_structures = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR get_acceleration_structure_device_address = nullptr;
};

class Buffer;

class Device {
 public:
  // index: a physical-device index as list_devices() numbers them; without it,
  // lavapipe ("llvmpipe") if present, else the first device with ray query
  // (for bvh: else the first device). `rayquery` requires ray query and
  // enables its extensions; `bvh` enables none of them, so it runs on devices
  // without (stock bookworm Mesa 22, NVIDIA H100/H200).
  // Set GIHARNESS_VALIDATION=1 to enable VK_LAYER_KHRONOS_validation (when installed).
  // A main device on lavapipe compiles its pipelines ahead (gpu/shader_prewarm.h)
  // unless validation is on, Mesa's disk cache is off, or the setting says 0.
  explicit Device(std::optional<int> index = std::nullopt, BackendRequest backend = BackendRequest::rayquery,
                  DeviceRole role = DeviceRole::main);
  ~Device();
  Device(Device&& other) noexcept;
  Device& operator=(Device&& other) noexcept;
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // "0: llvmpipe (LLVM 15.0.6, 256 bits) [ray query]" per physical device.
  static std::vector<std::string> list_devices();

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice handle() const { return device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  const DeviceInfo& info() const { return info_; }
  const KhrFunctions& khr() const { return khr_; }
  const VkPhysicalDeviceLimits& limits() const { return limits_; }
  // Size of the largest memory heap: what one scenario's buffers must fit in.
  std::uint64_t largest_heap_bytes() const;
  std::uint32_t min_scratch_offset_alignment() const { return min_scratch_alignment_; }
  bool validation_enabled() const { return validation_; }
  TraceBackend backend() const { return backend_; }
  // Buffers in device-local memory, moved through staging copies: on discrete
  // and virtual GPUs, where the CPU reads host-visible VRAM uncached over PCIe
  // (on an H200 that made readbacks 560x the GPU time). Not on CPU and
  // integrated devices (lavapipe), whose one memory is the host's. The
  // environment's GIHARNESS_BUFFER_MEMORY=staged|mapped overrides the choice
  // (tests run the staged path on lavapipe; benchmarks compare the two).
  bool staged_buffers() const { return staged_buffers_; }
  // A host-visible, preferably host-cached buffer of at least `bytes` for
  // staging copies; reused (grown when needed). Valid until the next call.
  Buffer& staging(VkDeviceSize bytes);
  // Bytes moved between host and buffers since the device was made (either
  // memory mode): what observing the pipeline costs in transfers.
  struct TransferCounts {
    std::uint64_t downloaded = 0, uploaded = 0, downloads = 0, uploads = 0;
  };
  const TransferCounts& transfers() const { return transfers_; }
  // Compute pipelines shared by this device's passes (gpu/pipeline_cache.h).
  PipelineCache& pipelines() { return *pipelines_; }
  // The compiles ahead of this device's pipelines; null where there are none.
  ShaderPrewarm* prewarm() { return prewarm_.get(); }
  void count_transfer(bool download, std::uint64_t bytes) {
    (download ? transfers_.downloaded : transfers_.uploaded) += bytes;
    ++(download ? transfers_.downloads : transfers_.uploads);
  }

  // Records with `record` into a fresh primary command buffer, submits it to
  // the compute queue and waits for it to finish.
  // Records, submits and waits. A submission that does not finish within
  // GIHARNESS_GPU_TIMEOUT_S seconds (default 300), or a lost device, ends the
  // process with exit code 3 after calling the fault handler: work may still be
  // in flight, so unwinding (which frees buffers the GPU may be using) is not
  // safe. The handler is where a caller saves what it has (nightly marks the
  // scenario and rewrites its summary).
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record);
  // The same in two halves, so the host can work while the GPU runs: submit
  // records and submits (after waiting for any submission still in flight:
  // one at a time), wait waits for it (nothing when none is in flight).
  void submit(const std::function<void(VkCommandBuffer)>& record);
  void wait();
  bool in_flight() const { return in_flight_ != VK_NULL_HANDLE; }
  static void set_fault_handler(std::function<void(const std::string& message)> handler);
  // The same end for a fault found elsewhere: the handler, the message, exit 3.
  [[noreturn]] static void fault(const std::string& message);

 private:
  void destroy() noexcept;

  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  DeviceInfo info_;
  KhrFunctions khr_;
  VkPhysicalDeviceLimits limits_{};
  std::uint32_t min_scratch_alignment_ = 256;
  bool validation_ = false;
  TraceBackend backend_ = TraceBackend::rayquery;
  bool staged_buffers_ = false;
  DeviceRole role_ = DeviceRole::main;
  bool recording_ = false;  // inside submit_and_wait's record callback
  VkCommandBuffer in_flight_ = VK_NULL_HANDLE;  // submitted, not yet waited for
  std::unique_ptr<Buffer> staging_;
  TransferCounts transfers_;
  std::unique_ptr<ShaderPrewarm> prewarm_;  // before pipelines_, which holds a pointer to it
  std::unique_ptr<PipelineCache> pipelines_;
};

}  // namespace gi::gpu
