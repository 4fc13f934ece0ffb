// The two reference path tracers' speed on the Cornell box at 320x180, each a
// Google Benchmark (they were DISABLED_ tests that printed figures: a timing
// is a figure, never a test's assertion, docs/design.md §12):
// - BM_EmbreeReferenceCornell: the Embree path tracer, 64 spp on 2 threads
//   (counters: rays per second, rays per path);
// - BM_GpuReferenceCornell: the GPU reference mode, one 1-spp frame per
//   iteration, its pass's GPU time as the manual time (the wall time beside
//   it as a counter), on the default device (`auto`: lavapipe where present).
//   build/tests/bench/giharness_reference_bench --benchmark_repetitions=3
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <optional>
#include <vector>

#include "core/cache_root.h"
#include "core/reference/embree_reference.h"
#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"

namespace {

constexpr std::uint32_t kWidth = 320, kHeight = 180;

void BM_EmbreeReferenceCornell(benchmark::State& state) {
  const gi::Scene scene = gi::make_cornell_box();
  gi::ReferenceOptions o;
  o.width = kWidth;
  o.height = kHeight;
  o.spp = 64;
  o.threads = 2;
  gi::render_reference(scene, {32, 18, 1});  // warm-up: Embree's first scene
  double rays = 0, seconds = 0;
  for (auto _ : state) {
    const gi::ReferenceResult r = gi::render_reference(scene, o);
    rays += double(r.rays);
    seconds += r.seconds;
    benchmark::DoNotOptimize(r.mean.pixels.data());
  }
  state.counters["Mrays_per_s"] = rays / seconds * 1e-6;
  state.counters["rays_per_path"] = rays / (double(state.iterations()) * kWidth * kHeight * o.spp);
}
BENCHMARK(BM_EmbreeReferenceCornell)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GpuReferenceCornell(benchmark::State& state) {
  // The shaders: the source checkout is a data folder (core/data_dir.h), unless one is set.
  ::setenv("GIHARNESS_DATA_DIR", GIHARNESS_SOURCE_DIR, 0);
  const gi::Scene scene = gi::make_cornell_box();
  const gi::FlatGeometry geometry = gi::flatten_geometry(scene);
  const gi::FlatInstances flat = gi::flatten_instances(scene, geometry);
  std::vector<bool> visible;
  for (const gi::Instance& i : scene.instances) visible.push_back(i.visible);
  gi::gpu::Device device(std::nullopt, gi::gpu::BackendRequest::automatic);
  gi::gpu::ShaderCompiler compiler(gi::cache_root());
  gi::gpu::RendererOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.gbuffer = false;
  gi::gpu::Renderer renderer(device, compiler, geometry, options);
  renderer.update_scene(flat, visible);
  const gi::GpuCamera camera = gi::make_gpu_camera(scene.camera, kWidth, kHeight);
  std::uint32_t frame = 0;
  auto render = [&] {
    renderer.render_frame(gi::frame_constants(camera, camera, flat, kWidth, kHeight, frame, 7, 1));
    ++frame;
  };
  render();  // the first dispatch compiles the pipeline (lavapipe)
  render();
  double wall_ms = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    render();
    wall_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    state.SetIterationTime(renderer.last_timings().at(0).ms * 1e-3);
  }
  state.counters["wall_ms"] = wall_ms / double(state.iterations());
  state.SetLabel(device.info().name + ", LP_NUM_THREADS=" + device.info().lp_num_threads);
}
BENCHMARK(BM_GpuReferenceCornell)->Unit(benchmark::kMillisecond)->UseManualTime();

}  // namespace

BENCHMARK_MAIN();
