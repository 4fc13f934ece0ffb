#include "replay/bench.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <map>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/bvh/embree_ray_caster.h"
#include "core/bvh/ray_sets.h"
#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/scene_flatten.h"
#include "core/scenes/cliff.h"
#include "core/scenes/cornell_box.h"
#include "gpu/device.h"
#include "gpu/passes/ray_trace_test.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "replay/run_scenario.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

constexpr int kRepeats = 3;  // ray-rate repetitions; the median is reported

Scene bench_scene(const std::string& name, const BenchOptions& o) {
  if (name == "cornell_box") return make_cornell_box();
  if (name == "glossy_room") return import_gltf(std::filesystem::path(GIHARNESS_SOURCE_DIR) / "scenarios/assets/glossy_room.gltf");
  if (name == "cliff") {
    CliffOptions c;
    c.triangles = o.cliff_triangles;
    return make_cliff_scene(c);
  }
  throw InputError("--scenes", "", fmt::format("cornell_box, glossy_room or cliff; got \"{}\"", name));
}

std::vector<bool> visibility_of(const Scene& scene) {
  std::vector<bool> v;
  for (const Instance& i : scene.instances) v.push_back(i.visible);
  return v;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
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
  renderer.update_scene(flat, visibility_of(scene));
  std::map<std::string, std::vector<double>> pass_ms;
  std::vector<double> frame_ms;
  for (std::uint32_t f = 0; f <= o.frames; ++f) {
    FrameConstants c{};
    c.camera = c.previous_camera = make_gpu_camera(scene.camera, o.width, o.height);
    c.resolution_frame = glm::uvec4(o.width, o.height, f, 1);
    c.counts = glm::uvec4(std::uint32_t(flat.lights.size()), flat.directional_light_count, o.spp, f * o.spp);
    renderer.render_frame(c);
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
  b->add_option("--frames", o.frames, "timed frames per scene")->capture_default_str();
  b->add_option("--spp", o.spp, "reference samples per pixel per frame")->capture_default_str();
  b->add_option("--backend", o.backend, "the pipeline's tracing backend")
      ->check(CLI::IsMember({"auto", "rayquery", "bvh"}))
      ->capture_default_str();
  b->add_option("--ray-backends", o.ray_backends, "backends whose ray rates to measure (skipped where unsupported)")
      ->delimiter(',')
      ->capture_default_str();
  b->add_option("--rays", o.rays, "diffuse rays per scene for the ray rates (0 = skip)")->capture_default_str();
  b->add_option("--cliff-triangles", o.cliff_triangles)->capture_default_str();
  b->add_option("--embree-threads", o.embree_threads, "0 = all cores")->capture_default_str();
  b->add_option("--device", o.device, "Vulkan device index");
  b->add_option("--out", o.out, "the JSON record")->capture_default_str();
  return b;
}

int run_bench(const BenchOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  gpu::ShaderCompiler compiler(cache_root() / "spirv");
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
                       {"rays", o.rays},           {"cliff_triangles", o.cliff_triangles},
                       {"embree_threads", o.embree_threads}};

  std::vector<Scene> scenes;
  for (const std::string& name : o.scenes) scenes.push_back(bench_scene(name, o));

  // 1. The pipeline at the benchmark resolution.
  {
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

  // 2. Ray rates: closest hits of the same diffuse rays per backend and Embree.
  nlohmann::json rays = nlohmann::json::object();
  if (o.rays > 0) {
    std::vector<std::vector<shader::TestRay>> ray_sets;
    std::vector<FlatGeometry> geometries;
    std::vector<FlatInstances> flats;
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      geometries.push_back(flatten_geometry(scenes[s]));
      flats.push_back(flatten_instances(scenes[s], geometries.back()));
      bvh::RaySetOptions ro;
      ro.count = o.rays;
      ro.kind = bvh::RayKind::diffuse;
      const auto set = bvh::make_ray_set(geometries.back(), flats.back(), visibility_of(scenes[s]), ro);
      ray_sets.push_back(to_test_rays(set));
      const bvh::EmbreeRayCaster embree(geometries.back(), flats.back(), visibility_of(scenes[s]));
      std::vector<double> wall;
      std::uint64_t hits = 0;
      for (int r = 0; r < kRepeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        hits = embree.closest_batch(set, o.embree_threads);
        wall.push_back(seconds_since(t0) * 1000.0);
      }
      rays[o.scenes[s]] = {{"rays", o.rays}, {"kind", "diffuse"}, {"triangles", scenes[s].triangle_count()}};
      rays[o.scenes[s]]["embree"] = rate(o.rays, median(wall));
      rays[o.scenes[s]]["embree"]["hits"] = hits;
      rays[o.scenes[s]]["embree"]["threads"] = o.embree_threads;
      spdlog::info("bench: {} Embree {:.2f} Mrays/s", o.scenes[s], o.rays / median(wall) / 1000.0);
    }
    for (const std::string& backend : o.ray_backends) {
      std::optional<gpu::Device> device;
      try {
        device.emplace(o.device, gpu::parse_backend_request(backend));
      } catch (const DeviceError& e) {
        for (const std::string& name : o.scenes) rays[name][backend] = {{"unavailable", e.what()}};
        continue;
      }
      for (std::size_t s = 0; s < scenes.size(); ++s) {
        gpu::RayTraceTest tracer(*device, compiler, geometries[s], flats[s], visibility_of(scenes[s]));
        std::vector<double> gpu_ms, wall_ms;
        std::uint64_t hits = 0;
        for (int r = 0; r <= kRepeats; ++r) {
          const auto t0 = std::chrono::steady_clock::now();
          const auto results = tracer.trace(ray_sets[s], shader::TRACE_MODE_CLOSEST);
          const double wall = seconds_since(t0) * 1000.0;
          if (r == 0) continue;  // warm-up
          gpu_ms.push_back(tracer.last_ms());
          wall_ms.push_back(wall);
          hits = 0;
          for (const auto& h : results) hits += h.flags & 1u;
        }
        nlohmann::json& j = rays[o.scenes[s]][backend];
        j = rate(o.rays, median(gpu_ms));
        j["hits"] = hits;
        j["wall_ms_with_upload_and_readback"] = json_figure(median(wall_ms));
        const double embree_ms = rays[o.scenes[s]]["embree"]["ms"].get<double>();
        j["over_embree"] = json_figure(embree_ms / median(gpu_ms));
        spdlog::info("bench: {} {} {:.2f} Mrays/s ({:.2f}x Embree)", o.scenes[s], backend,
                     o.rays / median(gpu_ms) / 1000.0, embree_ms / median(gpu_ms));
      }
    }
  }
  record["rays"] = rays;
  record["wall_seconds"] = json_figure(seconds_since(start));
  write_json_file(o.out, record);
  spdlog::info("bench: wrote {}", o.out.string());
  return 0;
}

}  // namespace gi
