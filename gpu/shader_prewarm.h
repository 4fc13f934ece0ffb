// Compiles a device's new compute pipelines ahead of their first dispatch, on
// worker threads, so that the compiles run side by side.
//
// lavapipe compiles a pipeline with LLVM, on its one queue thread, when the
// pipeline is first dispatched (gallium's llvmpipe builds the shader variant
// at launch, not at vkCreateComputePipelines); a run's GI passes then compile
// one after another on one core while the others wait. Each worker here has
// a VkDevice of its own on the same physical device: it creates the same
// pipeline (same SPIR-V, layout and push-constant range, through its own
// PipelineCache) and dispatches zero workgroups, which makes lavapipe compile
// it and store the code in Mesa's shader disk cache. The main device's first
// dispatch then finds the code there. It is the same code, so the output
// keeps its bits; without a disk cache (MESA_SHADER_CACHE_DISABLE) nothing is
// gained and the work is done twice, so the device turns this off there.
//
// A warm run must not pay for it: a worker's pipeline costs its SPIR-V
// translation again (10-640 ms each on lavapipe) and competes with the run's
// set-up. So each pipeline compiled ahead leaves a marker under the cache
// root (prewarmed/<Mesa cache location>/<pipeline and driver>), and a
// pipeline with a marker is not compiled ahead again. A marker outliving
// Mesa's entry (its cache cleared by hand, or an entry evicted) costs only
// the parallelism: the main device compiles that pipeline itself, as it would
// without this.
//
// The setting: GIHARNESS_SHADER_PREWARM_THREADS, the number of workers
// (0: off); without it, one per CPU core. `nightly --jobs N` gives each
// scenario its share of the cores, or none below two (app/nightly.cpp).
#pragma once
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "gpu/compute_pass.h"
#include "gpu/device.h"

namespace gi::gpu {

class ShaderPrewarm {
 public:
  // The workers' devices: physical device `device_index`, tracing `backend`;
  // `driver`: the device's name and driver version, part of each marker's key.
  ShaderPrewarm(int device_index, TraceBackend backend, std::string driver, unsigned threads);
  ~ShaderPrewarm();  // drops the pipelines not yet begun, waits for the rest
  ShaderPrewarm(const ShaderPrewarm&) = delete;
  ShaderPrewarm& operator=(const ShaderPrewarm&) = delete;

  // Queues a pipeline (what PipelineCache::get was given) and starts a worker
  // if one is free, unless its marker says it was compiled ahead before. The
  // largest SPIR-V is compiled first.
  void add(const std::string& name, std::span<const std::uint32_t> spirv, const std::vector<DescriptorBinding>& bindings,
           std::uint32_t push_constant_bytes);
  // Returns once every pipeline queued so far is compiled and its code in the
  // disk cache: the workers finish, and their devices are destroyed, which
  // flushes Mesa's cache writes (a thread of its own). Cheap when nothing is
  // queued: a pass calls it before each dispatch.
  void drain();

  // GIHARNESS_SHADER_PREWARM_THREADS, or the CPU cores when unset; throws
  // gi::InputError naming the variable when it is not a count.
  static unsigned threads_setting();

 private:
  struct Job {
    std::string name;
    std::vector<std::uint32_t> spirv;
    std::vector<DescriptorBinding> bindings;
    std::uint32_t push_bytes = 0;
    std::filesystem::path marker;
  };
  void work();

  int device_index_;
  TraceBackend backend_;
  unsigned threads_;
  std::filesystem::path marker_dir_;
  std::string driver_;
  std::mutex drain_mutex_;  // one drain at a time: a second caller waits for the first
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::deque<Job> queue_;
  std::vector<std::thread> workers_;
  bool finishing_ = false;  // drain or the destructor: workers end when the queue is empty
  bool failed_ = false;     // a worker could not make its device: no more workers
};

}  // namespace gi::gpu
