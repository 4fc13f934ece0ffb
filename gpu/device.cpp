#include "gpu/device.h"

#include <algorithm>
#include <cstdio>

#include <cstdlib>
#include <cctype>
#include <cstring>
#include <regex>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "gpu/buffer.h"
#include "gpu/pipeline_cache.h"
#include "gpu/shader_prewarm.h"

namespace gi::gpu {

namespace {

std::function<void(const std::string&)>& fault_handler() {
  static std::function<void(const std::string&)> handler;
  return handler;
}

std::uint64_t gpu_timeout_ns() {
  static const std::uint64_t ns = [] {
    const char* env = std::getenv("GIHARNESS_GPU_TIMEOUT_S");
    double seconds = 300.0;
    if (env && *env) {
      char* end = nullptr;
      const double v = std::strtod(env, &end);
      if (end != env && v >= 0.0 && v < 1e9) seconds = v;
    }
    return static_cast<std::uint64_t>(seconds * 1e9);
  }();
  return ns;
}

[[noreturn]] void gpu_fault(const std::string& message) {
  if (fault_handler()) {
    try {
      fault_handler()(message);
    } catch (...) {
    }
  }
  std::fprintf(stderr, "giharness: device error: %s\n", message.c_str());
  std::fflush(stderr);
  std::_Exit(3);
}

}  // namespace


const char* vk_result_name(VkResult result) {
  switch (result) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    case VK_ERROR_INVALID_SHADER_NV: return "VK_ERROR_INVALID_SHADER_NV";
    default: return "VkResult(?)";
  }
}

void check_vk(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw DeviceError(fmt::format("Vulkan: {} failed: {} ({})", what, vk_result_name(result), int(result)));
}

namespace {

const char* const kDeviceExtensions[] = {
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_RAY_QUERY_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
};

std::string version_string(std::uint32_t v) {
  return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
}

bool has_extension(VkPhysicalDevice pd, const char* name) {
  std::uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> ext(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, ext.data());
  for (const auto& e : ext)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

bool supports_ray_query(VkPhysicalDevice pd) {
  for (const char* e : kDeviceExtensions)
    if (!has_extension(pd, e)) return false;
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(pd, &p);
  return p.apiVersion >= VK_API_VERSION_1_2;
}

std::optional<std::uint32_t> compute_queue_family(VkPhysicalDevice pd) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  for (std::uint32_t i = 0; i < n; ++i)
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return i;
  return std::nullopt;
}

bool layer_available(const char* name) {
  std::uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

VkInstance create_instance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "giharness";
  app.apiVersion = VK_API_VERSION_1_2;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  if (validation) {
    ci.enabledLayerCount = 1;
    ci.ppEnabledLayerNames = &layer;
  }
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  if (r != VK_SUCCESS)
    throw DeviceError(fmt::format("Vulkan: no usable Vulkan 1.2 instance (vkCreateInstance: {}); "
                                  "is a Vulkan driver (mesa-vulkan-drivers) installed?",
                                  vk_result_name(r)));
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  std::uint32_t n = 0;
  check_vk(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(n);
  check_vk(vkEnumeratePhysicalDevices(instance, &n, devices.data()), "vkEnumeratePhysicalDevices");
  return devices;
}

std::vector<std::string> describe(const std::vector<VkPhysicalDevice>& devices) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devices[i], &p);
    out.push_back(fmt::format("{}: {} (Vulkan {}){}", i, p.deviceName, version_string(p.apiVersion),
                              supports_ray_query(devices[i]) ? " [ray query]" : " [no ray query]"));
  }
  return out;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += "\n  " + l;
  return lines.empty() ? std::string("\n  (none)") : s;
}

bool is_lavapipe(VkPhysicalDevice pd) {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(pd, &p);
  return std::strstr(p.deviceName, "llvmpipe") != nullptr;
}

const char* device_type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete_gpu";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated_gpu";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual_gpu";
    default: return "other";
  }
}

bool choose_staged_buffers(VkPhysicalDeviceType type) {
  const char* env = std::getenv("GIHARNESS_BUFFER_MEMORY");
  const std::string forced = env ? env : "";
  if (forced == "staged") return true;
  if (forced == "mapped") return false;
  if (!forced.empty())
    throw InputError("GIHARNESS_BUFFER_MEMORY", "", fmt::format("staged or mapped; got \"{}\"", forced));
  return type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU || type == VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU;
}

}  // namespace

const char* backend_name(TraceBackend backend) { return backend == TraceBackend::bvh ? "bvh" : "rayquery"; }

BackendRequest parse_backend_request(const std::string& text) {
  if (text == "auto") return BackendRequest::automatic;
  if (text == "rayquery") return BackendRequest::rayquery;
  if (text == "bvh") return BackendRequest::bvh;
  throw InputError("--backend", "", fmt::format("one of auto, rayquery, bvh; got \"{}\"", text));
}

nlohmann::json DeviceInfo::to_json() const {
  return nlohmann::json{{"name", name},
                        {"driver_name", driver_name},
                        {"driver_info", driver_info},
                        {"mesa_version", mesa_version},
                        {"llvm_version", llvm_version},
                        {"api_version", api_version},
                        {"vendor_id", vendor_id},
                        {"device_id", device_id},
                        {"subgroup_size", subgroup_size},
                        {"lp_num_threads", lp_num_threads},
                        {"timestamp_period_ns", timestamp_period_ns},
                        {"device_index", device_index},
                        {"ray_query", ray_query},
                        {"device_type", device_type},
                        {"backend", backend},
                        {"buffer_memory", buffer_memory}};
}

std::vector<std::string> Device::list_devices() {
  VkInstance instance = create_instance(false);
  std::vector<std::string> out;
  try {
    out = describe(physical_devices(instance));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return out;
}

namespace {

// Mesa's own reading of MESA_SHADER_CACHE_DISABLE (a boolean option).
bool mesa_disk_cache_disabled() {
  const char* env = std::getenv("MESA_SHADER_CACHE_DISABLE");
  if (!env) return false;
  std::string v(env);
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return v == "1" || v == "true" || v == "yes" || v == "y" || v == "t";
}

}  // namespace

Device::Device(std::optional<int> index, BackendRequest request, DeviceRole role) : role_(role) {
  const char* env_validation = std::getenv("GIHARNESS_VALIDATION");
  if (env_validation && std::string(env_validation) == "1") {
    validation_ = layer_available("VK_LAYER_KHRONOS_validation");
    if (!validation_) spdlog::warn("GIHARNESS_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not installed");
  }
  instance_ = create_instance(validation_);
  try {
    std::vector<VkPhysicalDevice> devices = physical_devices(instance_);
    std::vector<std::string> names = describe(devices);
    int chosen = -1;
    if (index) {
      if (*index < 0 || *index >= int(devices.size()))
        throw DeviceError(fmt::format("--device {} is out of range; Vulkan devices:{}", *index, join_lines(names)));
      if (request == BackendRequest::rayquery && !supports_ray_query(devices[*index]))
        throw DeviceError(fmt::format("device {} has no ray query (needs {} + {} + {}); Vulkan devices:{}", *index,
                                      kDeviceExtensions[0], kDeviceExtensions[1], kDeviceExtensions[2],
                                      join_lines(names)));
      chosen = *index;
    } else {
      for (std::size_t i = 0; i < devices.size() && chosen < 0; ++i) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(devices[i], &p);
        if (std::strstr(p.deviceName, "llvmpipe") &&
            (request != BackendRequest::rayquery || supports_ray_query(devices[i])))
          chosen = int(i);
      }
      for (std::size_t i = 0; i < devices.size() && chosen < 0; ++i)
        if (supports_ray_query(devices[i])) chosen = int(i);
      // The bvh backend needs only Vulkan 1.2 compute (every device here).
      if (chosen < 0 && request != BackendRequest::rayquery && !devices.empty()) chosen = 0;
      if (chosen < 0)
        throw DeviceError(fmt::format("no Vulkan device with ray query (lavapipe needs Mesa >= 24.1, "
                                      "mesa-vulkan-drivers from bookworm-backports); Vulkan devices:{}",
                                      join_lines(names)));
    }
    physical_ = devices[chosen];
    const bool has_ray_query = supports_ray_query(physical_);
    if (request == BackendRequest::bvh) backend_ = TraceBackend::bvh;
    else if (request == BackendRequest::rayquery) backend_ = TraceBackend::rayquery;
    else backend_ = (is_lavapipe(physical_) || !has_ray_query) ? TraceBackend::bvh : TraceBackend::rayquery;
    const bool want_ray_query = backend_ == TraceBackend::rayquery;
    std::optional<std::uint32_t> family = compute_queue_family(physical_);
    if (!family) throw DeviceError(fmt::format("device {} has no compute queue", chosen));
    queue_family_ = *family;

    // Properties for DeviceInfo.
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceAccelerationStructurePropertiesKHR as_props{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
    driver.pNext = &subgroup;
    if (has_ray_query) subgroup.pNext = &as_props;  // only structures of extensions the device has
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = &driver;
    vkGetPhysicalDeviceProperties2(physical_, &props);
    limits_ = props.properties.limits;
    min_scratch_alignment_ = std::max<std::uint32_t>(as_props.minAccelerationStructureScratchOffsetAlignment, 1);

    info_.name = props.properties.deviceName;
    info_.driver_name = driver.driverName;
    info_.driver_info = driver.driverInfo;
    std::smatch m;
    if (std::regex_search(info_.driver_info, m, std::regex(R"(Mesa ([^ ()]+))"))) info_.mesa_version = m[1];
    if (std::regex_search(info_.driver_info, m, std::regex(R"(LLVM ([0-9][0-9.]*))"))) info_.llvm_version = m[1];
    info_.api_version = version_string(props.properties.apiVersion);
    info_.vendor_id = props.properties.vendorID;
    info_.device_id = props.properties.deviceID;
    info_.subgroup_size = subgroup.subgroupSize;
    const char* threads = std::getenv("LP_NUM_THREADS");
    info_.lp_num_threads = threads && *threads ? threads : "default";
    info_.timestamp_period_ns = props.properties.limits.timestampPeriod;
    info_.device_index = chosen;
    info_.ray_query = has_ray_query;
    info_.backend = backend_name(backend_);
    staged_buffers_ = choose_staged_buffers(props.properties.deviceType);
    info_.device_type = device_type_name(props.properties.deviceType);
    info_.buffer_memory = staged_buffers_ ? "staged" : "mapped";

    // Features: bufferDeviceAddress -> accelerationStructure -> rayQuery (docs/design.md §4).
    VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    VkPhysicalDeviceAccelerationStructureFeaturesKHR asf{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features.pNext = &v12;
    if (has_ray_query) v12.pNext = &asf;
    asf.pNext = &rq;
    vkGetPhysicalDeviceFeatures2(physical_, &features);
    if (want_ray_query && (!v12.bufferDeviceAddress || !asf.accelerationStructure || !rq.rayQuery))
      throw DeviceError(fmt::format("device {} ({}) lacks bufferDeviceAddress/accelerationStructure/rayQuery",
                                    chosen, info_.name));
    // The observation passes (gpu/passes/frame_output.h, buffer_hash.h) hash
    // any buffer through its device address and sum luminance in double.
    if (!v12.bufferDeviceAddress || !features.features.shaderFloat64)
      throw DeviceError(fmt::format("device {} ({}) lacks bufferDeviceAddress or shaderFloat64", chosen, info_.name));

    VkPhysicalDeviceRayQueryFeaturesKHR rq_on{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    rq_on.rayQuery = VK_TRUE;
    VkPhysicalDeviceAccelerationStructureFeaturesKHR as_on{
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
    as_on.accelerationStructure = VK_TRUE;
    as_on.pNext = &rq_on;
    VkPhysicalDeviceVulkan12Features v12_on{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    v12_on.bufferDeviceAddress = v12.bufferDeviceAddress;
    v12_on.pNext = want_ray_query ? &as_on : nullptr;
    VkPhysicalDeviceFeatures2 features_on{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    features_on.features.shaderInt64 = features.features.shaderInt64;
    features_on.features.shaderFloat64 = VK_TRUE;
    features_on.pNext = &v12_on;

    float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queue_family_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &features_on;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    // The bvh backend enables no extension: it must run where none exist.
    dci.enabledExtensionCount = want_ray_query ? std::uint32_t(std::size(kDeviceExtensions)) : 0u;
    dci.ppEnabledExtensionNames = want_ray_query ? kDeviceExtensions : nullptr;
    check_vk(vkCreateDevice(physical_, &dci, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

    auto load = [&](auto& fn, const char* name) {
      fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(vkGetDeviceProcAddr(device_, name));
      if (!fn) throw DeviceError(fmt::format("Vulkan: vkGetDeviceProcAddr({}) returned null", name));
    };
    if (want_ray_query) {
      load(khr_.create_acceleration_structure, "vkCreateAccelerationStructureKHR");
      load(khr_.destroy_acceleration_structure, "vkDestroyAccelerationStructureKHR");
      load(khr_.get_acceleration_structure_build_sizes, "vkGetAccelerationStructureBuildSizesKHR");
      load(khr_.cmd_build_acceleration_structures, "vkCmdBuildAccelerationStructuresKHR");
      load(khr_.get_acceleration_structure_device_address, "vkGetAccelerationStructureDeviceAddressKHR");
    }

    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queue_family_;
    check_vk(vkCreateCommandPool(device_, &pci, nullptr, &pool_), "vkCreateCommandPool");
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check_vk(vkCreateFence(device_, &fci, nullptr, &fence_), "vkCreateFence");
    if (role == DeviceRole::main && info_.driver_name == "llvmpipe" && !validation_ && !mesa_disk_cache_disabled()) {
      const unsigned threads = ShaderPrewarm::threads_setting();
      if (threads > 0) prewarm_ = std::make_unique<ShaderPrewarm>(info_.device_index, backend_,
                                                            info_.name + " " + info_.driver_info, threads);
    }
    pipelines_ = std::make_unique<PipelineCache>(device_, prewarm_.get(), role == DeviceRole::main);
  } catch (...) {
    destroy();
    throw;
  }
  spdlog::debug("Vulkan device {}: {} ({})", info_.device_index, info_.name, info_.driver_info);
}

void Device::destroy() noexcept {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (in_flight_) vkFreeCommandBuffers(device_, pool_, 1, &in_flight_);
    in_flight_ = VK_NULL_HANDLE;
    staging_.reset();
    prewarm_.reset();
    pipelines_.reset();
    if (fence_) vkDestroyFence(device_, fence_, nullptr);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  instance_ = VK_NULL_HANDLE;
  device_ = VK_NULL_HANDLE;
  fence_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
}

Device::~Device() { destroy(); }

Device::Device(Device&& other) noexcept { *this = std::move(other); }

Device& Device::operator=(Device&& other) noexcept {
  if (this != &other) {
    destroy();
    instance_ = std::exchange(other.instance_, VK_NULL_HANDLE);
    physical_ = std::exchange(other.physical_, VK_NULL_HANDLE);
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    queue_ = std::exchange(other.queue_, VK_NULL_HANDLE);
    queue_family_ = other.queue_family_;
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    fence_ = std::exchange(other.fence_, VK_NULL_HANDLE);
    info_ = std::move(other.info_);
    khr_ = other.khr_;
    limits_ = other.limits_;
    min_scratch_alignment_ = other.min_scratch_alignment_;
    validation_ = other.validation_;
    backend_ = other.backend_;
    staged_buffers_ = other.staged_buffers_;
    role_ = other.role_;
    staging_ = std::move(other.staging_);
    transfers_ = other.transfers_;
    prewarm_ = std::move(other.prewarm_);
    pipelines_ = std::move(other.pipelines_);
    in_flight_ = std::exchange(other.in_flight_, VK_NULL_HANDLE);
  }
  return *this;
}

void Device::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  submit(record);
  wait();
}

void Device::submit(const std::function<void(VkCommandBuffer)>& record) {
  // A staged transfer inside a recording would submit from within a submission.
  if (recording_) throw std::logic_error("Device::submit_and_wait called while recording (a staged transfer?)");
  wait();  // one submission in flight at a time: a transfer between frames follows the frame
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check_vk(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  try {
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check_vk(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
    recording_ = true;
    try {
      record(cmd);
    } catch (...) {
      recording_ = false;
      throw;
    }
    recording_ = false;
    check_vk(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    check_vk(vkResetFences(device_, 1, &fence_), "vkResetFences");
    check_vk(vkQueueSubmit(queue_, 1, &si, fence_), "vkQueueSubmit");
  } catch (...) {
    vkFreeCommandBuffers(device_, pool_, 1, &cmd);
    throw;
  }
  in_flight_ = cmd;
}

void Device::wait() {
  if (in_flight_ == VK_NULL_HANDLE) return;
  // A prewarm worker's submission is a compile only, and its fault would end
  // the process from a worker thread: it waits as long as the compile takes.
  const VkResult waited = vkWaitForFences(device_, 1, &fence_, VK_TRUE,
                                          role_ == DeviceRole::shader_prewarm ? UINT64_MAX : gpu_timeout_ns());
  if (waited == VK_TIMEOUT || waited == VK_ERROR_DEVICE_LOST) {
    const std::string message =
        waited == VK_TIMEOUT
            ? fmt::format("GPU timeout: a submission did not finish within {} s (GIHARNESS_GPU_TIMEOUT_S) on {}",
                          double(gpu_timeout_ns()) * 1e-9, info_.name)
            : fmt::format("device lost (VK_ERROR_DEVICE_LOST) on {}", info_.name);
    gpu_fault(message);
  }
  check_vk(waited, "vkWaitForFences");
  vkFreeCommandBuffers(device_, pool_, 1, &in_flight_);
  in_flight_ = VK_NULL_HANDLE;
}

Buffer& Device::staging(VkDeviceSize bytes) {
  if (!staging_ || staging_->size() < bytes) {
    staging_.reset();  // free the old one first: staging can be as large as the largest buffer
    // Grow in powers of two so a run's readbacks settle on one buffer.
    VkDeviceSize size = 1 << 20;
    while (size < bytes) size *= 2;
    staging_ = std::make_unique<Buffer>(*this, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                        "staging", BufferMemory::staging);
  }
  return *staging_;
}

std::uint64_t Device::largest_heap_bytes() const {
  VkPhysicalDeviceMemoryProperties m{};
  vkGetPhysicalDeviceMemoryProperties(physical_, &m);
  std::uint64_t largest = 0;
  for (std::uint32_t i = 0; i < m.memoryHeapCount; ++i) largest = std::max<std::uint64_t>(largest, m.memoryHeaps[i].size);
  return largest;
}

void Device::set_fault_handler(std::function<void(const std::string& message)> handler) {
  fault_handler() = std::move(handler);
}

void Device::fault(const std::string& message) { gpu_fault(message); }

}  // namespace gi::gpu
