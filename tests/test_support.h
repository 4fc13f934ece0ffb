// Helpers shared by the tests: running commands and the giharness binary,
// temp directories, what the default Vulkan device offers (and skipping the
// tests that need what it lacks), and rendering the GPU reference of a scene
// in-process.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <system_error>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/scene.h"
#include "gpu/device.h"

namespace gi::test {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// A `giharness run`: its exit code and output, and its summary.json (empty
// when the run wrote none).
struct ScenarioRun {
  int exit_code = -1;
  std::string output;
  nlohmann::json summary;
};

// Runs `command` through /bin/sh, capturing stdout and stderr together;
// exit_code is -1 when it did not exit normally (a signal) or did not start.
CommandResult run_command(const std::string& command);

// Runs `giharness <args>` with extra environment assignments (e.g.
// "LP_NUM_THREADS=1"), capturing its output.
CommandResult run_giharness(const std::string& args, const std::string& env = "");

// A fresh directory under the system's temp folder, removed at exit of scope.
// Defined here, not in test_support.cpp: tests/fuzz/fuzz_targets.cpp uses it
// and is also built into the libFuzzer targets, which link gi_core alone.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("giharness-test-" + name + "-" + std::to_string(std::random_device{}()))) {
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

nlohmann::json read_json(const std::filesystem::path& file);

// The result of check `name` in <out>/summary.json (a test failure, and
// null, when the run has none).
nlohmann::json check_result(const std::filesystem::path& out, const std::string& name);

// A repository scenario (path relative to the source tree), changed by
// `edit` and written to <dir>/<file_name> without its "$schema"; returns the
// file's path.
std::filesystem::path write_scenario_variant(const std::string& scenario, const std::filesystem::path& dir,
                                             const std::string& file_name,
                                             const std::function<void(nlohmann::json&)>& edit);
// Runs a repository scenario for `frames` frames twice, as it is and with
// its checks cut to "finite", under <dir>/with and <dir>/without; returns the
// two summary.json documents (empty where a run failed, which it reports).
// For showing that a check's instrumentation leaves the pipeline's bits alone.
std::pair<nlohmann::json, nlohmann::json> run_with_and_without_checks(const std::string& scenario,
                                                                      const std::filesystem::path& dir, int frames);
// The file's bytes (empty when it cannot be read).
std::string read_text(const std::filesystem::path& file);

// ---- The Vulkan device the tests run on. Without --device, gpu::Device and
// `giharness` take lavapipe when present, else the first device with ray
// queries, else (backends bvh and auto) the first device (gpu/device.h). The
// suite runs on lavapipe (Mesa >= 24.1: ray queries), on bookworm's own Mesa
// 22 (`.ci/stock-mesa`: lavapipe without ray queries) and on NVIDIA H100/H200
// (no ray queries). Probed once per process.
struct DeviceSupport {
  std::string name;             // the device `--backend auto` runs on, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  bool lavapipe = false;        // that device is Mesa's lavapipe (its name holds "llvmpipe")
  std::string auto_backend;     // what `--backend auto` picks there: "bvh" on lavapipe and without ray queries
  bool ray_query = false;       // `--backend rayquery` finds a device (VK_KHR_ray_query + acceleration structures)
  std::string ray_query_error;  // else why not: gpu::Device's message, listing the devices
};
const DeviceSupport& device_support();

// The backend for in-process GPU tests that are not about a backend:
// `rayquery` where a device offers it (what their figures were measured with
// on lavapipe), else `bvh` (same hits; images agree with rayquery's to
// relMSE <= 1e-5, README "Tracing backends").
gpu::BackendRequest test_backend();

}  // namespace gi::test

// Skips the calling test (GTEST_SKIP, which returns from the function it is
// used in) when no device offers ray queries, naming the devices. For the
// tests of the `rayquery` backend itself: the backend comparisons and the
// `--backend rayquery` runs.
#define GI_SKIP_WITHOUT_RAY_QUERY()                                                                    \
  do {                                                                                                 \
    if (!::gi::test::device_support().ray_query)                                                       \
      GTEST_SKIP() << "needs a Vulkan device with ray queries (the rayquery backend); "                \
                   << ::gi::test::device_support().ray_query_error;                                   \
  } while (false)

namespace gi::test {

std::filesystem::path source_dir();

struct GpuReference {
  Image mean, half_a, half_b;
  std::uint64_t nonfinite_samples = 0;
};

// The GPU reference mode on test_backend(): `frames` frames of `spp` samples
// each, accumulated.
GpuReference render_gpu_reference(const Scene& scene, std::uint32_t width, std::uint32_t height,
                                  std::uint32_t frames, std::uint32_t spp, std::uint32_t seed);

}  // namespace gi::test
