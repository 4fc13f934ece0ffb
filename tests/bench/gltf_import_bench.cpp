// Importer speed on a scene of real size: glTF import (JSON, schema
// check, accessors, image decoding, MikkTSpace tangents), flattening for the
// GPU, the Embree BVH the reference builds and the `bvh` backend's BVH, each
// a Google Benchmark.
// Peak memory is the process's maximum resident set after the runs (a
// counter, "peak_rss_mb"). The file: $GIHARNESS_BENCH_GLTF, else the nightly's
// 1 M-triangle atrium that .ci/build generates.
//   build/tests/bench/giharness_gltf_import_bench --benchmark_repetitions=3
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <embree3/rtcore.h>

#include "core/bvh/scene_bvh.h"
#include "core/gltf_import.h"
#include "core/reference/embree_geometry.h"
#include "core/scene_flatten.h"

namespace {

std::filesystem::path bench_file() {
  if (const char* f = std::getenv("GIHARNESS_BENCH_GLTF"); f && *f) return f;
  return std::filesystem::path(GIHARNESS_SOURCE_DIR) / "scenarios/assets/generated/atrium_1m.glb";
}

void report_scene(benchmark::State& state, const gi::Scene& scene) {
  state.counters["triangles"] = double(scene.triangle_count());
  state.counters["materials"] = double(scene.materials.size());
  state.counters["images"] = double(scene.images.size());
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  state.counters["peak_rss_mb"] = double(u.ru_maxrss) / 1024.0;
}

void BM_ImportGltf(benchmark::State& state) {
  const auto file = bench_file();
  gi::Scene scene;
  for (auto _ : state) {
    scene = gi::import_gltf(file);
    benchmark::DoNotOptimize(scene.meshes.data());
  }
  report_scene(state, scene);
}
BENCHMARK(BM_ImportGltf)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FlattenForTheGpu(benchmark::State& state) {
  const gi::Scene scene = gi::import_gltf(bench_file());
  for (auto _ : state) {
    gi::FlatGeometry g = gi::flatten_geometry(scene);
    gi::FlatInstances f = gi::flatten_instances(scene, g);
    benchmark::DoNotOptimize(f.instances.data());
  }
  report_scene(state, scene);
}
BENCHMARK(BM_FlattenForTheGpu)->Unit(benchmark::kMillisecond)->UseRealTime();

// The Embree reference's BVH (its scene build flags, all instances attached).
void BM_EmbreeBvhBuild(benchmark::State& state) {
  const gi::Scene scene = gi::import_gltf(bench_file());
  const gi::FlatGeometry g = gi::flatten_geometry(scene);
  const gi::FlatInstances f = gi::flatten_instances(scene, g);
  RTCDevice device = rtcNewDevice(nullptr);
  for (auto _ : state) {
    RTCScene rtc = rtcNewScene(device);
    rtcSetSceneFlags(rtc, RTC_SCENE_FLAG_ROBUST);  // as core/reference/embree_bridge.cpp
    rtcSetSceneBuildQuality(rtc, RTC_BUILD_QUALITY_HIGH);
    for (std::uint32_t i = 0; i < f.instances.size(); ++i)
      if (!gi::attach_instance_geometry(device, rtc, g, f.instances[i], i)) state.SkipWithError("Embree out of memory");
    rtcCommitScene(rtc);
    rtcReleaseScene(rtc);
  }
  rtcReleaseDevice(device);
  report_scene(state, scene);
}
BENCHMARK(BM_EmbreeBvhBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

// The `bvh` backend's two-level BVH, built on the CPU before upload (binned
// SAH per mesh, then the TLAS over the instances).
void BM_ComputeBackendBvhBuild(benchmark::State& state) {
  const gi::Scene scene = gi::import_gltf(bench_file());
  const gi::FlatGeometry g = gi::flatten_geometry(scene);
  const gi::FlatInstances f = gi::flatten_instances(scene, g);
  for (auto _ : state) {
    gi::bvh::SceneBvh bvh(g);
    bvh.update(f.instances, scene.visible_instances());
    benchmark::DoNotOptimize(bvh.nodes().data());
  }
  report_scene(state, scene);
}
BENCHMARK(BM_ComputeBackendBvhBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
