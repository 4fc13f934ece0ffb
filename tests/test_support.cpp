#include "tests/test_support.h"

#include <array>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <tuple>
#include <utility>

#include <sys/wait.h>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/scene_flatten.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "replay/run_scenario.h"

namespace gi::test {

CommandResult run_command(const std::string& command) {
  const std::string cmd = "{ " + command + "\n} 2>&1";
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

CommandResult run_giharness(const std::string& args, const std::string& env) {
  CommandResult r = run_command(env + (env.empty() ? "" : " ") + GIHARNESS_BINARY + std::string(" ") + args);
  // Each run's wall breakdown line (replay/wall_breakdown.h, it names the
  // scenario) goes to the test's own output, so that ctest's log
  // (--output-junit, -V) says which run of a slow test took the time and how
  // much of it was the driver's compile.
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);)
    if (line.find(": wall ") != std::string::npos) std::cout << line << "\n";
  return r;
}

nlohmann::json read_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

nlohmann::json check_result(const std::filesystem::path& out, const std::string& name) {
  const nlohmann::json summary = read_json(out / "summary.json");
  if (summary.contains("checks"))
    for (const auto& c : summary["checks"])
      if (c.value("name", "") == name) return c;
  ADD_FAILURE() << "no " << name << " result in " << out;
  return nullptr;
}

std::filesystem::path write_scenario_variant(const std::string& scenario, const std::filesystem::path& dir,
                                             const std::string& file_name,
                                             const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json doc = read_json(source_dir() / scenario);
  doc.erase("$schema");
  edit(doc);
  const std::filesystem::path file = dir / file_name;
  std::ofstream(file) << doc.dump(1);
  return file;
}

std::pair<nlohmann::json, nlohmann::json> run_with_and_without_checks(const std::string& scenario,
                                                                      const std::filesystem::path& dir, int frames) {
  const auto with = write_scenario_variant(scenario, dir, "with.json", [&](nlohmann::json& doc) { doc["frames"] = frames; });
  const auto without = write_scenario_variant(scenario, dir, "without.json", [&](nlohmann::json& doc) {
    doc["frames"] = frames;
    doc["checks"] = {{{"name", "finite"}}};
  });
  std::pair<nlohmann::json, nlohmann::json> summaries;
  for (const auto& [file, out, summary] : {std::tuple{with, dir / "with", &summaries.first},
                                           std::tuple{without, dir / "without", &summaries.second}}) {
    const auto r = run_giharness("run " + file.string() + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    if (std::filesystem::exists(out / "summary.json")) *summary = read_json(out / "summary.json");
  }
  return summaries;
}

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::filesystem::path source_dir() { return GIHARNESS_SOURCE_DIR; }

const DeviceSupport& device_support() {
  static const DeviceSupport support = [] {
    DeviceSupport s;
    {
      const gpu::Device device(std::nullopt, gpu::BackendRequest::automatic);
      s.name = device.info().name;
      s.lavapipe = s.name.find("llvmpipe") != std::string::npos;
      s.auto_backend = gpu::backend_name(device.backend());
    }
    try {
      const gpu::Device device(std::nullopt, gpu::BackendRequest::rayquery);
      s.ray_query = true;
    } catch (const DeviceError& e) {
      s.ray_query_error = e.what();
    }
    return s;
  }();
  return support;
}

gpu::BackendRequest test_backend() {
  return device_support().ray_query ? gpu::BackendRequest::rayquery : gpu::BackendRequest::bvh;
}

GpuReference render_gpu_reference(const Scene& scene, std::uint32_t width, std::uint32_t height,
                                  std::uint32_t frames, std::uint32_t spp, std::uint32_t seed) {
  gpu::Device device(std::nullopt, test_backend());
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
