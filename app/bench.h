// `giharness bench`: a GPU benchmark record (docs/design.md §12) in one command.
// Per scene (Cornell box, the glTF glossy room, a procedural cliff): the
// pipeline's per-pass GPU times at a large resolution (default 1600×900),
// and ray rates of the tracing backends against Embree rtcIntersect1 on the
// same diffuse rays. Writes one JSON record with the device and driver.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace gi {

struct BenchOptions {
  std::vector<std::string> scenes = {"cornell_box", "glossy_room", "cliff"};
  std::uint32_t width = 1600, height = 900;
  std::uint32_t frames = 8;             // timed frames per scene (after one warm-up frame)
  std::uint32_t spp = 1;                // reference samples per pixel per frame
  std::string backend = "auto";         // the pipeline's backend
  std::vector<std::string> ray_backends = {"bvh", "rayquery"};  // ray rates: each the device offers
  std::uint32_t rays = 1u << 20;        // diffuse rays per scene for the ray rates
  std::uint32_t cliff_triangles = 70000;
  unsigned embree_threads = 0;          // 0 = all cores
  std::optional<int> device;
  std::filesystem::path out = "reports/benchmarks/bench.json";
};

CLI::App* add_bench_subcommand(CLI::App& app, BenchOptions& options);
int run_bench(const BenchOptions& options);

}  // namespace gi
