#include "app/bench.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdlib>
#include <map>
#include <memory>

#include <sys/resource.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/bvh/embree_ray_caster.h"
#include "core/bvh/ray_sets.h"
#include "core/data_dir.h"
#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/scene_flatten.h"
#include "core/scenes/cliff.h"
#include "core/scenes/cornell_box.h"
#include "gpu/device.h"
#include "gpu/passes/ray_list_trace.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "replay/run_scenario.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

Scene bench_scene(const std::string& name, const BenchOptions& o) {
  if (name == "cornell_box") return make_cornell_box();
  if (name == "glossy_room") return import_gltf(data_dir() / "scenarios/assets/glossy_room.gltf");
  if (name == "cliff") {
    CliffOptions c;
    c.triangles = o.cliff_triangles;
    return make_cliff_scene(c);
  }
  throw InputError("--scenes", "", fmt::format("cornell_box, glossy_room or cliff; got \"{}\"", name));
}

// Timed repeats of the ray rates (--ray-repeats). Here rather than in
// BenchOptions (replay/bench.h) only to keep this measurement option local.
std::uint32_t ray_repeats = 5;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// CPU seconds of the whole process (every thread): a load-independent proxy
// beside the wall-clock rates, since on a shared machine both tracers lose
// wall time to other processes but not CPU time.
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The pipeline (primary visibility, G-buffer, GPU reference path tracer) at
// the benchmark resolution: per-pass GPU ms over the timed frames.
nlohmann::json time_pipeline(gpu::Device& device, gpu::ShaderCompiler& compiler, const Scene& scene,
                             const BenchOptions& o) {
  const FlatGeometry geometry = flatten_geometry(scene);
  const FlatInstances flat = flatten_instances(scene, geometry);
  gpu::RendererOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  ro.gbuffer = true;
  ro.reference = true;
  gpu::Renderer renderer(device, compiler, geometry, ro);
  renderer.update_scene(flat, scene.visible_instances());
  std::map<std::string, std::vector<double>> pass_ms;
  std::vector<double> frame_ms;
  for (std::uint32_t f = 0; f <= o.frames; ++f) {
    const GpuCamera camera = make_gpu_camera(scene.camera, o.width, o.height);
    renderer.render_frame(frame_constants(camera, camera, flat, o.width, o.height, f, 1, o.spp));
    if (f == 0) continue;  // warm-up: first-use costs (pipeline JIT on lavapipe)
    double sum = 0.0;
    for (const auto& t : renderer.last_timings()) {
      pass_ms[t.name].push_back(t.ms);
      sum += t.ms;
    }
    frame_ms.push_back(sum);
  }
  nlohmann::json j = timing_summary(pass_ms);
  j["frame_median_ms"] = json_figure(median(frame_ms));
  j["backend"] = gpu::backend_name(device.backend());
  return j;
}

std::vector<shader::TestRay> to_test_rays(const std::vector<bvh::TraceRay>& rays) {
  std::vector<shader::TestRay> out;
  out.reserve(rays.size());
  for (const auto& r : rays) out.push_back({glm::vec4(r.origin, r.tmax), glm::vec4(r.direction, 0.0f)});
  return out;
}

nlohmann::json rate(double rays, double ms) {
  return {{"ms", json_figure(ms)}, {"mrays_per_s", json_figure(ms > 0.0 ? rays / ms / 1000.0 : 0.0)}};
}

}  // namespace

CLI::App* add_bench_subcommand(CLI::App& app, BenchOptions& o) {
  CLI::App* b = app.add_subcommand("bench", "GPU benchmark record: per-pass ms at a large resolution and ray rates "
                                            "of the tracing backends vs Embree, as one JSON file");
  b->add_option("--scenes", o.scenes, "cornell_box, glossy_room, cliff")->delimiter(',')->capture_default_str();
  b->add_option("--width", o.width)->capture_default_str();
  b->add_option("--height", o.height)->capture_default_str();
  b->add_option("--frames", o.frames, "timed frames per scene (0 = ray rates only)")->capture_default_str();
  b->add_option("--spp", o.spp, "reference samples per pixel per frame")->capture_default_str();
  b->add_option("--backend", o.backend, "the pipeline's tracing backend")
      ->check(CLI::IsMember({"auto", "rayquery", "bvh"}))
      ->capture_default_str();
  b->add_option("--ray-backends", o.ray_backends, "backends whose ray rates to measure (skipped where unsupported)")
      ->delimiter(',')
      ->capture_default_str();
  b->add_option("--rays", o.rays, "diffuse rays per scene for the ray rates (0 = skip)")->capture_default_str();
  b->add_option("--ray-repeats", ray_repeats, "timed repeats of the ray rates, Embree and backends interleaved")
      ->capture_default_str();
  b->add_option("--cliff-triangles", o.cliff_triangles)->capture_default_str();
  b->add_option("--embree-threads", o.embree_threads, "0 = all cores")->capture_default_str();
  b->add_option("--device", o.device, "Vulkan device index");
  b->add_option("--out", o.out, "the JSON record")->capture_default_str();
  return b;
}

int run_bench(const BenchOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  gpu::ShaderCompiler compiler(cache_root());
  nlohmann::json record;
  record["schema_version"] = 1;
  record["kind"] = "giharness bench";
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  record["date"] = date;
  record["build"] = build_info();
  record["options"] = {{"scenes", o.scenes},       {"resolution", {o.width, o.height}},
                       {"frames", o.frames},       {"spp", o.spp},
                       {"backend", o.backend},     {"ray_backends", o.ray_backends},
                       {"rays", o.rays},           {"ray_repeats", ray_repeats},
                       {"cliff_triangles", o.cliff_triangles},
                       {"embree_threads", o.embree_threads}};

  std::vector<Scene> scenes;
  for (const std::string& name : o.scenes) scenes.push_back(bench_scene(name, o));

  // 1. The pipeline at the benchmark resolution (--frames 0 skips it).
  if (o.frames > 0) {
    gpu::Device device(o.device, gpu::parse_backend_request(o.backend));
    record["device"] = device.info().to_json();
    nlohmann::json pipeline = nlohmann::json::object();
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      spdlog::info("bench: {} pipeline at {}x{} ({})", o.scenes[s], o.width, o.height,
                   gpu::backend_name(device.backend()));
      pipeline[o.scenes[s]] = time_pipeline(device, compiler, scenes[s], o);
      pipeline[o.scenes[s]]["triangles"] = scenes[s].triangle_count();
    }
    record["pipeline"] = pipeline;
  }

  // 2. Ray rates: closest hits of the same diffuse rays per backend and Embree,
  // interleaved (Embree, then each backend, per repeat) so that both see the
  // same machine load; the ratio is reported per repeat (median, min, max)
  // beside the ratio of the medians.
  nlohmann::json rays = nlohmann::json::object();
  if (o.rays > 0) {
    double load[3] = {0.0, 0.0, 0.0};
    std::vector<std::optional<gpu::Device>> devices(o.ray_backends.size());
    std::vector<std::string> unavailable(o.ray_backends.size());
    for (std::size_t b = 0; b < o.ray_backends.size(); ++b) {
      try {
        devices[b].emplace(o.device, gpu::parse_backend_request(o.ray_backends[b]));
        if (!record.contains("device")) record["device"] = devices[b]->info().to_json();
      } catch (const DeviceError& e) {
        unavailable[b] = e.what();
      }
    }
    const int repeats = int(std::max<std::uint32_t>(ray_repeats, 1));
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      const FlatGeometry geometry = flatten_geometry(scenes[s]);
      const FlatInstances flat = flatten_instances(scenes[s], geometry);
      bvh::RaySetOptions ro;
      ro.count = o.rays;
      ro.kind = bvh::RayKind::diffuse;
      const auto set = bvh::make_ray_set(geometry, flat, scenes[s].visible_instances(), ro);
      const std::vector<shader::TestRay> test_rays = to_test_rays(set);
      const bvh::EmbreeRayCaster embree(geometry, flat, scenes[s].visible_instances());
      std::vector<std::unique_ptr<gpu::RayListTrace>> tracers(o.ray_backends.size());
      for (std::size_t b = 0; b < o.ray_backends.size(); ++b) {
        if (!devices[b]) continue;
        tracers[b] = std::make_unique<gpu::RayListTrace>(*devices[b], compiler, geometry, flat,
                                                         scenes[s].visible_instances());
        tracers[b]->trace(test_rays, shader::TRACE_MODE_CLOSEST);  // warm-up: pipeline JIT on lavapipe
      }
      embree.closest_batch(set, o.embree_threads);  // warm-up
      std::vector<double> embree_ms, embree_cpu_ms;
      std::vector<std::vector<double>> gpu_ms(o.ray_backends.size()), wall_ms(o.ray_backends.size()),
          ratio(o.ray_backends.size()), cpu_ms(o.ray_backends.size()), cpu_ratio(o.ray_backends.size());
      std::uint64_t embree_hits = 0;
      std::vector<std::uint64_t> hits(o.ray_backends.size(), 0);
      for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = process_cpu_seconds();
        embree_hits = embree.closest_batch(set, o.embree_threads);
        embree_ms.push_back(seconds_since(t0) * 1000.0);
        embree_cpu_ms.push_back((process_cpu_seconds() - c0) * 1000.0);
        for (std::size_t b = 0; b < o.ray_backends.size(); ++b) {
          if (!tracers[b]) continue;
          const auto t1 = std::chrono::steady_clock::now();
          const double c1 = process_cpu_seconds();
          const auto results = tracers[b]->trace(test_rays, shader::TRACE_MODE_CLOSEST);
          wall_ms[b].push_back(seconds_since(t1) * 1000.0);
          cpu_ms[b].push_back((process_cpu_seconds() - c1) * 1000.0);
          cpu_ratio[b].push_back(embree_cpu_ms.back() / cpu_ms[b].back());
          gpu_ms[b].push_back(tracers[b]->last_ms());
          ratio[b].push_back(embree_ms.back() / gpu_ms[b].back());
          hits[b] = 0;
          for (const auto& h : results) hits[b] += h.flags & 1u;
        }
      }
      nlohmann::json& scene_json = rays[o.scenes[s]];
      scene_json = {{"rays", o.rays}, {"kind", "diffuse"}, {"triangles", scenes[s].triangle_count()},
                    {"repeats", repeats}};
      scene_json["embree"] = rate(o.rays, median(embree_ms));
      scene_json["embree"]["hits"] = embree_hits;
      scene_json["embree"]["threads"] = o.embree_threads;
      scene_json["embree"]["cpu_ms"] = json_figure(median(embree_cpu_ms));
      spdlog::info("bench: {} Embree {:.2f} Mrays/s", o.scenes[s], o.rays / median(embree_ms) / 1000.0);
      for (std::size_t b = 0; b < o.ray_backends.size(); ++b) {
        const std::string& backend = o.ray_backends[b];
        if (!tracers[b]) {
          scene_json[backend] = {{"unavailable", unavailable[b]}};
          continue;
        }
        nlohmann::json& j = scene_json[backend];
        j = rate(o.rays, median(gpu_ms[b]));
        j["hits"] = hits[b];
        j["wall_ms_with_upload_and_readback"] = json_figure(median(wall_ms[b]));
        j["over_embree"] = json_figure(median(embree_ms) / median(gpu_ms[b]));
        const auto [lo, hi] = std::minmax_element(ratio[b].begin(), ratio[b].end());
        j["over_embree_per_repeat"] = {{"median", json_figure(median(ratio[b]))},
                                       {"min", json_figure(*lo)},
                                       {"max", json_figure(*hi)}};
        // CPU backends only (lavapipe): the process's CPU time around the
        // whole trace() call, upload and readback included.
        const auto [clo, chi] = std::minmax_element(cpu_ratio[b].begin(), cpu_ratio[b].end());
        j["cpu_ms_with_upload_and_readback"] = json_figure(median(cpu_ms[b]));
        j["over_embree_cpu_time_per_repeat"] = {{"median", json_figure(median(cpu_ratio[b]))},
                                                {"min", json_figure(*clo)},
                                                {"max", json_figure(*chi)}};
        spdlog::info("bench: {} {} {:.2f} Mrays/s ({:.3f}x Embree; per repeat median {:.3f}, {:.3f}-{:.3f}; "
                     "CPU time {:.3f}, {:.3f}-{:.3f})",
                     o.scenes[s], backend, o.rays / median(gpu_ms[b]) / 1000.0,
                     median(embree_ms) / median(gpu_ms[b]), median(ratio[b]), *lo, *hi, median(cpu_ratio[b]), *clo,
                     *chi);
      }
    }
    if (getloadavg(load, 3) == 3) record["load_average"] = {load[0], load[1], load[2]};
  }
  record["rays"] = rays;
  record["wall_seconds"] = json_figure(seconds_since(start));
  write_json_file(o.out, record);
  spdlog::info("bench: wrote {}", o.out.string());
  return 0;
}

}  // namespace gi
