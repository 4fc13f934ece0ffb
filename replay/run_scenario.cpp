#include "replay/run_scenario.h"

#include <chrono>
#include <cstdlib>
#include <map>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <xxhash.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/metrics.h"
#include "core/png_preview.h"
#include "core/scene_builder.h"
#include "core/scene_flatten.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "replay/checks/cluster_ids_check.h"
#include "replay/checks/realtime_reference_check.h"
#include "replay/checks/reference_check.h"
#include "replay/realtime_settings.h"
#include "core/profile.h"
#include "replay/events.h"
#include "replay/frame_log.h"
#include "replay/resource_limits.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

// Checks this build can run; the others are accepted by the scenario format
// (DESIGN §6) but refused here with a clear message rather than skipped.
const std::set<std::string> kImplementedChecks = {"reference", "finite", "cluster_ids"};

std::vector<bool> visibility_of(const Scene& scene) {
  std::vector<bool> v;
  for (const Instance& i : scene.instances) v.push_back(i.visible);
  return v;
}

std::string image_hash(const Image& image) {
  return fmt::format("{:016x}", XXH3_64bits(image.pixels.data(), image.pixels.size() * sizeof(glm::vec3)));
}

}  // namespace

std::filesystem::path cache_root() {
  if (const char* dir = std::getenv("GIHARNESS_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "giharness";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "giharness";
  return std::filesystem::temp_directory_path() / "giharness-cache";
}

RunResult run_scenario(const Scenario& scenario, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::uint32_t frames = options.frames.value_or(scenario.frames);
  const std::uint32_t seed = options.seed.value_or(scenario.seed);
  const std::uint32_t width = scenario.resolution[0], height = scenario.resolution[1];
  if (frames == 0) throw InputError("--frames", "", "expected a frame count of at least 1");
  // cluster_ids "count_only": walk the events and count IDs; no device, nothing drawn.
  if (const CheckSpec* spec = scenario.find_check("cluster_ids"); spec && cluster_ids_params(*spec, scenario).count_only)
    return run_cluster_ids_count_only(scenario, frames, options);
  // Realtime mode: the DI signal (light tiles + ReSTIR DI) under the resolved profile.
  const bool realtime = scenario.mode == RenderMode::Realtime;
  const Profile profile = resolve_profile(scenario, options.profile, options.sets);
  for (const CheckSpec& c : scenario.checks)
    if (!kImplementedChecks.count(c.name))
      throw InputError(scenario.file.string(), c.json_path + "/name",
                       fmt::format("a check this build implements (reference, finite, cluster_ids); \"{}\" is not built yet",
                                   c.name));

  const Scene initial = build_scene(scenario);
  for (const std::string& w : initial.warnings) spdlog::warn("{}: {}", scenario.name, w);
  Scene scene = initial;

  std::set<std::uint32_t> captures(scenario.capture.begin(), scenario.capture.end());
  captures.insert(options.capture.begin(), options.capture.end());
  for (std::uint32_t f : captures)
    if (f >= frames) throw InputError(scenario.file.string(), "/capture", fmt::format("frames below {}", frames));

  std::optional<ReferenceCheck> reference_check;
  std::optional<RealtimeReferenceCheck> realtime_check;
  if (const CheckSpec* spec = scenario.find_check("reference"); spec && realtime)
    realtime_check.emplace(reference_check_params(*spec, scenario, frames), seed, cache_root() / "reference",
                           options.out_dir);
  else if (spec)
    reference_check.emplace(reference_check_params(*spec, scenario, frames), seed, cache_root() / "reference",
                            options.out_dir);
  const bool finite_check = scenario.has_check("finite");
  // Walks the spawns first: an overflowing spawn is named before anything is drawn.
  std::optional<ClusterIdsCheck> cluster_ids_check;
  if (const CheckSpec* spec = scenario.find_check("cluster_ids")) {
    cluster_ids_check.emplace(cluster_ids_params(*spec, scenario), scenario, initial, frames);
    if (const auto& o = cluster_ids_check->overflow())
      spdlog::error("{}: cluster_ids: spawn {} ({}, frame {}) will overflow {} cluster bits: {} > {}", scenario.name,
                    o->instance, o->event, o->frame, cluster_ids_check->params().layout.cluster_bits, o->ids_after,
                    o->limit);
  }

  check_resource_limits(scenario, initial, 0);
  gpu::Device device(options.device, gpu::parse_backend_request(options.backend));
  check_resource_limits(scenario, initial, device.largest_heap_bytes());
  gpu::ShaderCompiler compiler(cache_root() / "spirv");
  FlatGeometry geometry = flatten_geometry(scene);
  gpu::RendererOptions renderer_options;
  renderer_options.width = width;
  renderer_options.height = height;
  renderer_options.gbuffer = !captures.empty() || cluster_ids_check;  // only what this scenario uses
  renderer_options.reference = !realtime;
  if (realtime) {
    renderer_options.gbuffer = true;
    renderer_options.di =
        di_settings_from_profile(profile, flatten_instances(scene, geometry), realtime_check ? 2u : 1u);
  }
  auto renderer = std::make_unique<gpu::Renderer>(device, compiler, geometry, renderer_options);
  if (cluster_ids_check)
    renderer->set_cluster_ids(cluster_ids_check->mesh_cluster_ids(scene, geometry), cluster_ids_check->params().layout);
  FlatInstances flat = flatten_instances(scene, geometry);
  renderer->update_scene(flat, visibility_of(scene));

  FrameLog frame_log(options.out_dir / "frames.jsonl");
  std::uint64_t window_samples = 0;
  std::uint32_t window_start = 0;
  std::optional<std::uint32_t> first_nonfinite_frame;
  std::uint64_t nonfinite_pixels_total = 0;
  nlohmann::json capture_files = nlohmann::json::array();
  GpuCamera previous_camera = make_gpu_camera(scene.camera, width, height);
  Image last_mean;

  for (std::uint32_t frame = 0; frame < frames; ++frame) {
    const ChangeSet changes = apply_events(scene, initial, scenario, frame);
    if (changes.geometry) {
      geometry = flatten_geometry(scene);
      renderer = std::make_unique<gpu::Renderer>(device, compiler, geometry, renderer_options);
      if (cluster_ids_check)
        renderer->set_cluster_ids(cluster_ids_check->mesh_cluster_ids(scene, geometry),
                                  cluster_ids_check->params().layout);
    }
    if (changes.any()) {
      flat = flatten_instances(scene, geometry);
      renderer->update_scene(flat, visibility_of(scene));
    }
    // The reference mode estimates one static image: any change starts a new
    // accumulation window.
    if (changes.any() && frame > 0) {
      renderer->reset_accumulation();
      window_samples = 0;
      window_start = frame;
    }

    FrameConstants constants{};
    constants.camera = make_gpu_camera(scene.camera, width, height);
    constants.previous_camera = frame == 0 ? constants.camera : previous_camera;
    constants.resolution_frame = glm::uvec4(width, height, frame, seed);
    // Sample indices depend on the frame only, so a replay from any frame
    // draws the same numbers.
    constants.counts = glm::uvec4(static_cast<std::uint32_t>(flat.lights.size()), flat.directional_light_count,
                                  scenario.samples_per_frame, frame * scenario.samples_per_frame);
    renderer->render_frame(constants);
    previous_camera = constants.camera;
    window_samples += scenario.samples_per_frame;

    nlohmann::json timings = nlohmann::json::object();
    for (const auto& t : renderer->last_timings()) timings[t.name] = json_figure(t.ms);
    last_mean = realtime ? renderer->di().frame(0) : renderer->reference_mean();
    const std::uint64_t nonfinite_samples = realtime ? 0 : renderer->reference_nonfinite_samples();
    const std::uint64_t nonfinite_pixels = count_nonfinite(last_mean);
    nonfinite_pixels_total += nonfinite_pixels;
    if ((nonfinite_pixels > 0 || nonfinite_samples > 0) && !first_nonfinite_frame)
      first_nonfinite_frame = frame;
    nlohmann::json record = {{"frame", frame},
                         {"window_start", window_start},
                         {"window_samples", window_samples},
                         {"mean_luminance", json_figure(mean_luminance(last_mean))},
                         {"nonfinite_pixels", nonfinite_pixels},
                         {"nonfinite_samples", nonfinite_samples},
                         {"pass_ms", timings}};
    if (cluster_ids_check)
      record["cluster_ids"] =
          cluster_ids_check->record_frame(frame, renderer->packed_visibility(), renderer->cluster_table());
    frame_log.add(record);

    if (captures.count(frame)) {
      // Realtime: the halves are chains A and B of this frame (or A twice with one chain).
      const Image a = realtime ? renderer->di().frame(0) : renderer->reference_half(0);
      const Image b = realtime ? renderer->di().frame(renderer->di().settings().chains - 1)
                               : renderer->reference_half(1);
      std::vector<Image> layers;
      const std::vector<std::string> names = {"albedo", "normal", "depth", "motion"};
      for (const std::string& n : names) layers.push_back(renderer->gbuffer_layer(n));
      std::vector<std::pair<std::string, const Image*>> exr = {{"", &last_mean}, {"half_a", &a}, {"half_b", &b}};
      for (std::size_t i = 0; i < names.size(); ++i) exr.emplace_back(names[i], &layers[i]);
      const std::string file = fmt::format("captures/frame_{:05}.exr", frame);
      write_exr(options.out_dir / file, exr);
      write_png_preview(options.out_dir / fmt::format("captures/frame_{:05}.png", frame), last_mean);
      capture_files.push_back(file);
    }
    if (realtime_check && realtime_check->wants(frame)) {
      const gpu::DiPipeline& di = renderer->di();
      RealtimeEstimate estimate{di.frame(0), di.frame(1), di.mean(0), di.mean(1), window_start,
                                di.accumulated_frames(0)};
      realtime_check->compare_frame(frame, scene, estimate);
    }
    if (reference_check && reference_check->wants(frame)) {
      GpuEstimate estimate{last_mean, renderer->reference_half(0), renderer->reference_half(1), window_samples};
      reference_check->compare_frame(frame, scene, estimate);
    }
    if (!options.quiet && (frame + 1) % 16 == 0)
      spdlog::info("{}: frame {}/{}", scenario.name, frame + 1, frames);
  }

  RunResult result;
  if (reference_check) result.checks.push_back(reference_check->result());
  if (realtime_check) result.checks.push_back(realtime_check->result());
  if (cluster_ids_check) result.checks.push_back(cluster_ids_check->result());
  if (finite_check) {
    CheckResult c;
    c.name = "finite";
    c.figures = {{"nonfinite_samples", realtime ? 0 : renderer->reference_nonfinite_samples()},
                 {"nonfinite_pixels", nonfinite_pixels_total}};
    c.limits = {{"nonfinite", 0}};
    c.first_failing_frame = first_nonfinite_frame;
    c.verdict = first_nonfinite_frame ? Verdict::fail : Verdict::pass;
    c.message = first_nonfinite_frame ? fmt::format("non-finite values from frame {}", *first_nonfinite_frame)
                                      : "no NaN or inf in any sample or output pixel";
    result.checks.push_back(c);
  }
  bool all_pass = true;
  nlohmann::json checks = nlohmann::json::array();
  for (const CheckResult& c : result.checks) {
    all_pass = all_pass && c.passed();
    checks.push_back(c.to_json());
  }
  result.exit_code = all_pass ? 0 : 1;

  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  nlohmann::json& s = result.summary;
  s["schema_version"] = 1;
  s["scenario"] = {{"name", scenario.name}, {"file", scenario.file.string()}, {"document", scenario.raw}};
  s["resolved"] = {{"resolution", {width, height}},
                   {"frames", frames},
                   {"seed", seed},
                   {"profile", scenario.profile},
                   {"overrides", scenario.overrides},
                   {"mode", realtime ? "realtime" : "reference"},
                   {"profile_values", profile.to_json()},
                   {"samples_per_frame", scenario.samples_per_frame},
                   {"backend", gpu::backend_name(device.backend())}};
  s["scene"] = {{"name", initial.name},
                {"instances", initial.instances.size()},
                {"triangles", initial.triangle_count()},
                {"lights", flat.lights.size()},
                {"warnings", initial.warnings}};
  s["device"] = device.info().to_json();
  s["build"] = build_info();
  s["verdict"] = all_pass ? "pass" : "fail";
  s["exit_code"] = result.exit_code;
  s["checks"] = checks;
  // Timing statistics over the kept records: every frame up to the log's
  // capacity, a regular subsample of longer runs (frames_log says which).
  const nlohmann::json kept_frames = frame_log.kept();
  std::map<std::string, std::vector<double>> pass_ms;
  for (const nlohmann::json& f : kept_frames)
    for (const auto& [name, ms] : f["pass_ms"].items())
      if (ms.is_number()) pass_ms[name].push_back(ms.get<double>());
  s["timings"] = timing_summary(pass_ms);
  s["frames"] = kept_frames;
  frame_log.finish();
  s["frames_log"] = {{"file", "frames.jsonl"}, {"records", frame_log.count()}, {"kept_every", frame_log.stride()}};
  s["final_image_hash"] = image_hash(last_mean);
  s["captures"] = capture_files;
  s["wall_seconds"] = json_figure(wall);
  write_json_file(options.out_dir / "summary.json", s);

  for (const CheckResult& c : result.checks)
    spdlog::log(c.passed() ? spdlog::level::info : spdlog::level::err, "{}: check {} {}: {}", scenario.name, c.name,
                to_string(c.verdict), c.message);
  return result;
}

}  // namespace gi
