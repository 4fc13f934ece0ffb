#include "gpu/shader_prewarm.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include <xxhash.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/cache_root.h"
#include "core/errors.h"
#include "core/phase_clock.h"
#include "gpu/pipeline_cache.h"

namespace gi::gpu {

namespace {

std::string hex64(std::uint64_t v) { return fmt::format("{:016x}", v); }

// Where Mesa keeps its cache, as far as it follows from the environment: a
// marker is only good for the cache it was written beside.
std::string mesa_cache_location() {
  std::string where;
  for (const char* name : {"MESA_SHADER_CACHE_DIR", "XDG_CACHE_HOME", "HOME"}) {
    const char* v = std::getenv(name);
    where += fmt::format("{}={};", name, v ? v : "");
  }
  return hex64(XXH3_64bits(where.data(), where.size()));
}

}  // namespace

ShaderPrewarm::ShaderPrewarm(int device_index, TraceBackend backend, std::string driver, unsigned threads)
    : device_index_(device_index),
      backend_(backend),
      threads_(threads),
      marker_dir_(cache_root() / "prewarmed" / mesa_cache_location()),
      driver_(std::move(driver)) {}

ShaderPrewarm::~ShaderPrewarm() {
  {
    std::lock_guard lock(mutex_);
    queue_.clear();
  }
  drain();
}

unsigned ShaderPrewarm::threads_setting() {
  const char* env = std::getenv("GIHARNESS_SHADER_PREWARM_THREADS");
  if (!env || !*env) return std::max(1u, std::thread::hardware_concurrency());
  char* end = nullptr;
  const long v = std::strtol(env, &end, 10);
  if (*end != '\0' || v < 0 || v > 256)
    throw InputError("GIHARNESS_SHADER_PREWARM_THREADS", "",
                     fmt::format("a count of worker threads from 0 (off) to 256, not '{}'", env));
  return unsigned(v);
}

void ShaderPrewarm::add(const std::string& name, std::span<const std::uint32_t> spirv,
                        const std::vector<DescriptorBinding>& bindings, std::uint32_t push_constant_bytes) {
  XXH3_state_t* h = XXH3_createState();
  XXH3_64bits_reset(h);
  XXH3_64bits_update(h, driver_.data(), driver_.size());
  XXH3_64bits_update(h, spirv.data(), spirv.size_bytes());
  for (const DescriptorBinding& b : bindings) {
    const std::uint32_t pair[2] = {b.binding, std::uint32_t(b.type)};
    XXH3_64bits_update(h, pair, sizeof pair);
  }
  XXH3_64bits_update(h, &push_constant_bytes, sizeof push_constant_bytes);
  std::filesystem::path marker = marker_dir_ / hex64(XXH3_64bits_digest(h));
  XXH3_freeState(h);
  std::error_code ec;
  if (std::filesystem::exists(marker, ec)) return;
  std::lock_guard lock(mutex_);
  if (failed_) return;
  queue_.push_back({name, {spirv.begin(), spirv.end()}, bindings, push_constant_bytes, std::move(marker)});
  if (workers_.size() < threads_) workers_.emplace_back([this] { work(); });
  work_ready_.notify_one();
}

void ShaderPrewarm::drain() {
  const std::lock_guard drain_lock(drain_mutex_);
  std::vector<std::thread> workers;
  {
    std::lock_guard lock(mutex_);
    if (workers_.empty()) return;
    finishing_ = true;
    workers.swap(workers_);
  }
  work_ready_.notify_all();
  {
    const PhaseScope timed(phase::kShaderPrewarm);
    for (std::thread& t : workers) t.join();
  }
  std::lock_guard lock(mutex_);
  finishing_ = false;
  // A worker that failed left its jobs: the main device compiles them itself.
  queue_.clear();
}

void ShaderPrewarm::work() {
  try {
    // Its own device, untimed: the main thread's wait in drain() is the time
    // this costs the run.
    Device device(device_index_, backend_ == TraceBackend::bvh ? BackendRequest::bvh : BackendRequest::rayquery,
                  DeviceRole::shader_prewarm);
    for (;;) {
      Job job;
      {
        std::unique_lock lock(mutex_);
        work_ready_.wait(lock, [this] { return !queue_.empty() || finishing_; });
        if (queue_.empty()) return;  // finishing
        const auto largest = std::max_element(queue_.begin(), queue_.end(), [](const Job& a, const Job& b) {
          return a.spirv.size() < b.spirv.size();
        });
        job = std::move(*largest);
        queue_.erase(largest);
      }
      const auto start = std::chrono::steady_clock::now();
      const SharedPipeline& p = device.pipelines().get(job.name, job.spirv, job.bindings, job.push_bytes);
      device.submit_and_wait([&](VkCommandBuffer cmd) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
        vkCmdDispatch(cmd, 0, 0, 0);
      });
      spdlog::debug("pass '{}': compiled ahead in {:.0f} ms", job.name,
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
      // An empty file; a marker not written costs the next run a compile ahead.
      std::error_code ec;
      std::filesystem::create_directories(job.marker.parent_path(), ec);
      if (!ec) std::ofstream(job.marker).close();
    }
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    if (!failed_) spdlog::warn("shader prewarm off for this run: {}", e.what());
    failed_ = true;
  }
}

}  // namespace gi::gpu
