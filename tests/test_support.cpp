#include "tests/test_support.h"

#include <array>
#include <cstdio>
#include <fstream>
#include <random>

#include <sys/wait.h>

#include "core/scene_flatten.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "replay/run_scenario.h"

namespace gi::test {

CommandResult run_giharness(const std::string& args, const std::string& env) {
  const std::string cmd = env + (env.empty() ? "" : " ") + GIHARNESS_BINARY + std::string(" ") + args + " 2>&1";
  CommandResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TempDir::TempDir(const std::string& name) {
  std::random_device rd;
  path_ = std::filesystem::temp_directory_path() / ("giharness-test-" + name + "-" + std::to_string(rd()));
  std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

nlohmann::json read_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

std::filesystem::path source_dir() { return GIHARNESS_SOURCE_DIR; }

GpuReference render_gpu_reference(const Scene& scene, std::uint32_t width, std::uint32_t height,
                                  std::uint32_t frames, std::uint32_t spp, std::uint32_t seed) {
  gpu::Device device;
  gpu::ShaderCompiler compiler(cache_root());
  const FlatGeometry geometry = flatten_geometry(scene);
  const FlatInstances flat = flatten_instances(scene, geometry);
  gpu::RendererOptions options;
  options.width = width;
  options.height = height;
  options.gbuffer = false;
  gpu::Renderer renderer(device, compiler, geometry, options);
  std::vector<bool> visible;
  for (const Instance& i : scene.instances) visible.push_back(i.visible);
  renderer.update_scene(flat, visible);
  for (std::uint32_t f = 0; f < frames; ++f) {
    FrameConstants c{};
    c.camera = c.previous_camera = make_gpu_camera(scene.camera, width, height);
    c.resolution_frame = glm::uvec4(width, height, f, seed);
    c.counts = glm::uvec4(static_cast<std::uint32_t>(flat.lights.size()), flat.directional_light_count, spp, f * spp);
    renderer.render_frame(c);
  }
  return {renderer.reference_mean(), renderer.reference_half(0), renderer.reference_half(1),
          renderer.reference_nonfinite_samples()};
}

}  // namespace gi::test
