// Helpers shared by the end-to-end tests: running the giharness binary, temp
// directories, and rendering the GPU reference of a scene in-process.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/scene.h"

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

// Runs `giharness <args>` with extra environment assignments (e.g.
// "LP_NUM_THREADS=1"), capturing its output.
CommandResult run_giharness(const std::string& args, const std::string& env = "");

// A fresh directory under the build's temp folder, removed at exit of scope.
class TempDir {
 public:
  explicit TempDir(const std::string& name);
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

nlohmann::json read_json(const std::filesystem::path& file);

std::filesystem::path source_dir();

struct GpuReference {
  Image mean, half_a, half_b;
  std::uint64_t nonfinite_samples = 0;
};

// The GPU reference mode: `frames` frames of `spp` samples each, accumulated.
GpuReference render_gpu_reference(const Scene& scene, std::uint32_t width, std::uint32_t height,
                                  std::uint32_t frames, std::uint32_t spp, std::uint32_t seed);

}  // namespace gi::test
