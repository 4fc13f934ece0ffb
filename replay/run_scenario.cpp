#include "replay/run_scenario.h"

#include <algorithm>
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
#include "replay/capture.h"
#include "replay/checks/blend_lag_check.h"
#include "replay/checks/cache_lifetime_check.h"
#include "replay/checks/cluster_ids_check.h"
#include "replay/checks/determinism_check.h"
#include "replay/checks/jacobian_check.h"
#include "replay/failure_capture.h"
#include "replay/signal_noise.h"
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

Image sum_images(const Image& a, const Image& b) {
  Image s = a;
  for (std::size_t i = 0; i < s.pixels.size(); ++i) s.pixels[i] += b.pixels[i];
  return s;
}

std::string image_hash(const Image& image) {
  return fmt::format("{:016x}", XXH3_64bits(image.pixels.data(), image.pixels.size() * sizeof(glm::vec3)));
}

}  // namespace

RunResult run_scenario(const Scenario& scenario, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::uint32_t frames = options.frames.value_or(scenario.frames);
  const std::uint32_t seed = options.seed.value_or(scenario.seed);
  const std::uint32_t width = scenario.resolution[0], height = scenario.resolution[1];
  if (frames == 0) throw InputError("--frames", "", "expected a frame count of at least 1");
  // cluster_ids "count_only": walk the events and count IDs; no device, nothing drawn.
  if (const CheckSpec* spec = scenario.find_check("cluster_ids"); spec && cluster_ids_params(*spec, scenario).count_only)
    return run_cluster_ids_count_only(scenario, frames, options);
  // Realtime mode: DI (light tiles + ReSTIR DI), with "gi" also ReSTIR GI,
  // specular GI and the world cache, under the resolved profile.
  const bool realtime = scenario.mode == RenderMode::Realtime;
  const Profile profile = resolve_profile(scenario, options.profile, options.sets);

  const Scene initial = build_scene(scenario);
  for (const std::string& w : initial.warnings) spdlog::warn("{}: {}", scenario.name, w);
  Scene scene = initial;

  // The scenario's own captures past a shortened run (--frames) are skipped
  // with a note (schema.json: "frames past the run are never reached"); a
  // --capture past it is a mistake on the command line.
  std::set<std::uint32_t> captures;
  nlohmann::json skipped_captures = nlohmann::json::array();
  for (std::uint32_t f : scenario.capture) {
    if (f < frames) {
      captures.insert(f);
      continue;
    }
    skipped_captures.push_back(f);
    spdlog::warn("{}: capture at frame {} skipped: the run has {} frames (--frames)", scenario.name, f, frames);
  }
  for (std::uint32_t f : options.capture) {
    if (f >= frames)
      throw InputError("--capture", "", fmt::format("frame {} is past the run's last frame {}", f, frames - 1));
    captures.insert(f);
  }
  std::optional<DeterminismParams> determinism;
  if (const CheckSpec* spec = scenario.find_check("determinism")) {
    determinism = determinism_params(*spec, scenario, frames);
    if (determinism->snapshot_frame) captures.insert(*determinism->snapshot_frame);
  }
  // Captures carry the run's hashes (replay --verify), replays record theirs.
  const bool record_hashes = options.record_hashes || !captures.empty() || determinism || !options.resume_from.empty();

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
  gpu::ShaderCompiler compiler(cache_root());
  FlatGeometry geometry = flatten_geometry(scene);
  gpu::RendererOptions renderer_options;
  renderer_options.width = width;
  renderer_options.height = height;
  // Only what this scenario uses; runs that record hashes (captures, replays,
  // the determinism check) always list the same buffers, G-buffer included.
  renderer_options.gbuffer = !captures.empty() || cluster_ids_check || record_hashes;
  renderer_options.reference = !realtime;
  if (realtime) {
    renderer_options.gbuffer = true;
    renderer_options.di = di_settings_from_profile(profile, flatten_instances(scene, geometry),
                                                   realtime_check || scenario.noise ? 2u : 1u,
                                                   scenario.gi && profile.flag("specular.enabled"));
  }
  // ReSTIR GI + specular GI ("gi": true): the output becomes DI + GI + specular.
  const bool gi = realtime && scenario.gi;
  if (scenario.gi && !realtime)
    throw InputError(scenario.file.string(), "/gi", "\"gi\": true in \"mode\": \"realtime\" only");
  std::optional<JacobianCheck> jacobian_check;
  if (const CheckSpec* spec = scenario.find_check("jacobian")) {
    if (!gi)
      throw InputError(scenario.file.string(), spec->json_path + "/name",
                       "the jacobian check reads ReSTIR GI: a realtime scenario with \"gi\": true");
    jacobian_check.emplace(jacobian_check_params(*spec, scenario, profile.number("restir_gi.jacobian_reject")));
  }
  if (gi) renderer_options.gi = gi_settings_from_profile(profile, realtime_check || scenario.noise ? 2u : 1u);
  // The world cache runs when GI queries it (or the debug view); the
  // root-frame instrumentation is compiled in only for cache_lifetime.
  std::optional<CacheLifetimeCheck> cache_lifetime_check;
  std::optional<BlendLagParams> blend_lag;
  std::map<std::string, BlendLagSignal> blend_lag_signals;  // every available signal, per frame
  if (scenario.cache_view && !realtime)
    throw InputError(scenario.file.string(), "/cache_view", "\"cache_view\": true in \"mode\": \"realtime\" only");
  // Without the debug view only GI's queries put cells in the cache.
  const bool cache_fed = scenario.cache_view || (renderer_options.gi && renderer_options.gi->queries_world_cache());
  for (const char* name : {"cache_lifetime", "blend_lag"}) {
    const CheckSpec* spec = scenario.find_check(name);
    if (spec && !realtime)
      throw InputError(scenario.file.string(), spec->json_path + "/name",
                       fmt::format("\"{}\" reads the world cache, which runs in \"mode\": \"realtime\" only", name));
    if (spec && !cache_fed)
      throw InputError(scenario.file.string(), spec->json_path + "/name",
                       fmt::format("\"{}\" reads the world cache, which only GI's queries fill: set \"gi\": true "
                                   "(restir_gi.hit_radiance world_cache), or the debug \"cache_view\": true",
                                   name));
  }
  if (const CheckSpec* spec = scenario.find_check("cache_lifetime"))
    cache_lifetime_check.emplace(cache_lifetime_params(
        *spec, scenario, static_cast<std::uint32_t>(profile.integer("world_cache.lifetime")), frames));
  if (const CheckSpec* spec = scenario.find_check("blend_lag")) blend_lag = blend_lag_params(*spec, scenario);
  // The world cache runs when something queries it.
  if (cache_fed) {
    gpu::WorldCacheSettings cache = world_cache_settings_from_profile(profile);
    cache.view = scenario.cache_view;
    cache.stats = true;
    cache.root_frame = cache_lifetime_check.has_value();
    renderer_options.world_cache = cache;
  }
  auto renderer = std::make_unique<gpu::Renderer>(device, compiler, geometry, renderer_options);
  if (cluster_ids_check)
    renderer->set_cluster_ids(cluster_ids_check->mesh_cluster_ids(scene, geometry), cluster_ids_check->params().layout);
  FlatInstances flat = flatten_instances(scene, geometry);
  renderer->update_scene(flat, scene.visible_instances());

  FrameLog frame_log(options.out_dir / "frames.jsonl");
  std::uint64_t window_samples = 0;
  std::uint32_t window_start = 0;  // first frame of the accumulated estimate
  std::uint32_t static_start = 0;  // last frame the scene changed (start of the static window)
  const std::uint32_t warmup_frames = realtime_check ? realtime_check->params().warmup_frames : 0;
  std::optional<std::uint32_t> first_nonfinite_frame;
  std::uint64_t nonfinite_pixels_total = 0;
  std::uint64_t gi_nonfinite_total = 0;  // non-finite GI reservoirs and GI/specular output values
  nlohmann::json capture_files = nlohmann::json::array();
  GpuCamera previous_camera = make_gpu_camera(scene.camera, width, height);
  Image last_mean;
  // The realtime output of one chain: DI, plus GI and specular when enabled.
  auto realtime_frame = [&](std::uint32_t chain) {
    Image img = renderer->di().frame(chain);
    if (gi) img = sum_images(sum_images(img, renderer->gi().gi_frame(chain)), renderer->gi().specular_frame(chain));
    return img;
  };
  auto realtime_mean = [&](std::uint32_t chain) {
    Image img = renderer->di().mean(chain);
    if (gi) img = sum_images(sum_images(img, renderer->gi().gi_mean(chain)), renderer->gi().specular_mean(chain));
    return img;
  };
  std::optional<FrameLog> hash_log;
  if (record_hashes) hash_log.emplace(options.out_dir / "buffer_hashes.jsonl");
  auto state_hashes = [&](std::uint32_t frame) {
    gpu::StateList state;
    renderer->list_state(state);
    return hash_record(frame, state);
  };
  std::uint32_t first_frame = 0;
  if (!options.resume_from.empty()) {
    // Replay: the scene at the captured frame (events are a pure function of
    // the frame), the pipeline rebuilt for it, its state and the loop's restored.
    const Capture capture = read_capture(options.resume_from);
    const std::string manifest = (capture.dir / "manifest.json").string();
    if (capture.frame + 1 >= frames)
      throw InputError(manifest, "/frame", fmt::format("a frame before the run's last ({} frames)", frames));
    scene = scene_at_frame(initial, scenario, capture.frame);
    geometry = flatten_geometry(scene);
    renderer.reset();  // one pipeline's buffers at a time
    renderer = std::make_unique<gpu::Renderer>(device, compiler, geometry, renderer_options);
    if (cluster_ids_check)
      renderer->set_cluster_ids(cluster_ids_check->mesh_cluster_ids(scene, geometry), cluster_ids_check->params().layout);
    flat = flatten_instances(scene, geometry);
    renderer->update_scene(flat, scene.visible_instances());
    restore_capture(capture, *renderer);
    const nlohmann::json& loop = capture.manifest["loop"];
    if (loop.value("scene_hash", "") != scene_hash(flat))
      spdlog::warn("{}: the scene re-derived at frame {} differs from the captured one (scenario or code changed?)",
                   manifest, capture.frame);
    window_start = loop.value("window_start", 0u);
    static_start = loop.value("static_start", window_start);
    window_samples = loop.value("window_samples", std::uint64_t{0});
    nonfinite_pixels_total = loop.value("nonfinite_pixels_total", std::uint64_t{0});
    if (loop.contains("first_nonfinite_frame") && loop["first_nonfinite_frame"].is_number_unsigned())
      first_nonfinite_frame = loop["first_nonfinite_frame"].get<std::uint32_t>();
    previous_camera = make_gpu_camera(scene.camera, width, height);
    nlohmann::json restored = state_hashes(capture.frame);
    restored["restored"] = true;  // the state as restored, before any replayed frame
    hash_log->add(restored);
    first_frame = capture.frame + 1;
  }
  std::vector<std::uint32_t> captured_frames;
  // Each signal's per-frame noise at `frame`, from chains A and B
  // (chain_noise), relative to the temporal mean of the whole output, so the
  // signals' figures add up to about the output's (issue 25's measure).
  nlohmann::json s_noise = nullptr;
  TemporalNoise temporal_noise;
  const std::uint32_t temporal_noise_start = std::max(first_frame, frames / 2);
  auto realtime_noise = [&](std::uint32_t frame) {
    Image mean = realtime_mean(0);
    const Image mean_b = realtime_mean(1);
    for (std::size_t i = 0; i < mean.pixels.size(); ++i) mean.pixels[i] = 0.5f * (mean.pixels[i] + mean_b.pixels[i]);
    // Each chain's signals, read back once.
    std::map<std::string, Image> a, b;
    for (auto [chain, out] : {std::pair{0u, &a}, std::pair{1u, &b}}) {
      (*out)["di"] = renderer->di().frame(chain);
      (*out)["output"] = (*out)["di"];
      if (gi) {
        (*out)["gi"] = renderer->gi().gi_frame(chain);
        (*out)["specular"] = renderer->gi().specular_frame(chain);
        (*out)["output"] = sum_images(sum_images((*out)["output"], (*out)["gi"]), (*out)["specular"]);
      }
    }
    nlohmann::json signals = nlohmann::json::object();
    for (const auto& [name, image] : a) signals[name] = json_figure(chain_noise(image, b.at(name), mean));
    return nlohmann::json{{"frame", frame},
                          {"method", "per-frame relMSE of one chain against its expectation: mean over pixels and "
                                     "channels of (A - B)^2 / 2 / (m^2 + 0.01), A and B the two chains' signal at "
                                     "this frame, m the temporal mean of the output (both chains)"},
                          {"signals", signals}};
  };

  for (std::uint32_t frame = first_frame; frame < frames; ++frame) {
    const ChangeSet changes = apply_events(scene, initial, scenario, frame);
    // Spawns update the acceleration structures and scene buffers in place:
    // reservoirs, the world cache and every other pass's history carry on
    // (Bevy's Solari keeps them across scene changes). Only a spawned
    // generated mesh changes the flat geometry; meshes are only appended.
    if (changes.geometry) check_resource_limits(scenario, scene, device.largest_heap_bytes());
    if (changes.geometry && scene.meshes.size() != geometry.meshes.size()) {
      geometry = flatten_geometry(scene);
      renderer->update_geometry(geometry);
      if (cluster_ids_check)
        renderer->set_cluster_ids(cluster_ids_check->mesh_cluster_ids(scene, geometry),
                                  cluster_ids_check->params().layout);
    }
    if (changes.any()) {
      flat = flatten_instances(scene, geometry);
      renderer->update_scene(flat, scene.visible_instances());
    }
    // The reference mode estimates one static image: any change starts a new
    // accumulation window.
    if (changes.any() && frame > 0) static_start = frame;
    // A realtime reference check with warmup_frames starts its window that
    // many frames into the static window.
    if ((changes.any() && frame > 0) || (warmup_frames > 0 && frame == static_start + warmup_frames)) {
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
    // Realtime: chain A's signals, read back once; each signal's mean
    // luminance goes into the frame record.
    nlohmann::json signal_luminance = nullptr;
    double gi_luminance = 0.0;
    if (realtime) {
      const Image di_image = renderer->di().frame(0);
      Image gi_image, specular_image;
      last_mean = di_image;
      signal_luminance = {{"di", json_figure(mean_luminance(di_image))}};
      if (gi) {
        gi_image = renderer->gi().gi_frame(0);
        specular_image = renderer->gi().specular_frame(0);
        gi_luminance = mean_luminance(gi_image);
        signal_luminance["gi"] = json_figure(gi_luminance);
        signal_luminance["specular"] = json_figure(mean_luminance(specular_image));
        last_mean = sum_images(sum_images(last_mean, gi_image), specular_image);
      }
      // The temporal noise window: the second half of the run, restarted by
      // any change of the scene.
      if (frame == temporal_noise_start || (changes.any() && frame > temporal_noise_start))
        temporal_noise.restart(frame);
      if (frame >= temporal_noise_start) {
        std::map<std::string, const Image*> signals = {{"output", &last_mean}, {"di", &di_image}};
        if (gi) {
          signals["gi"] = &gi_image;
          signals["specular"] = &specular_image;
        }
        temporal_noise.add(signals);
      }
    } else {
      last_mean = renderer->reference_mean();
    }
    const std::uint64_t nonfinite_samples = realtime ? 0 : renderer->reference_nonfinite_samples();
    const std::uint64_t nonfinite_pixels = count_nonfinite(last_mean);
    nonfinite_pixels_total += nonfinite_pixels;
    std::optional<gpu::GiFrameStats> gi_stats;
    if (gi) gi_stats = renderer->gi().stats();
    const std::uint64_t gi_nonfinite = gi_stats ? gi_stats->nonfinite_reservoirs + gi_stats->nonfinite_output : 0;
    gi_nonfinite_total += gi_nonfinite;
    if ((nonfinite_pixels > 0 || nonfinite_samples > 0 || gi_nonfinite > 0) && !first_nonfinite_frame)
      first_nonfinite_frame = frame;
    const double output_luminance = mean_luminance(last_mean);
    nlohmann::json record = {{"frame", frame},
                         {"window_start", window_start},
                         {"window_samples", window_samples},
                         {"mean_luminance", json_figure(output_luminance)},
                         {"nonfinite_pixels", nonfinite_pixels},
                         {"nonfinite_samples", nonfinite_samples},
                         {"pass_ms", timings}};
    if (realtime) record["signal_mean_luminance"] = signal_luminance;
    if (gi_stats)
      record["gi"] = jacobian_check ? jacobian_check->record_frame(frame, *gi_stats)
                                    : nlohmann::json{{"merges", gi_stats->merges},
                                                     {"rejections", gi_stats->rejections},
                                                     {"max_accepted_j", json_figure(gi_stats->max_accepted_j)},
                                                     {"nonfinite_reservoirs", gi_stats->nonfinite_reservoirs},
                                                     {"nonfinite_output", gi_stats->nonfinite_output}};
    if (cluster_ids_check)
      record["cluster_ids"] =
          cluster_ids_check->record_frame(frame, renderer->packed_visibility(), renderer->cluster_table());
    if (renderer_options.world_cache) {
      const gpu::WorldCacheFrameStats cache = renderer->world_cache().stats();
      record["world_cache"] = {{"active_cells", cache.active_cells},
                               {"live_cells", cache.live_cells},
                               {"mean_radiance", json_figure(cache.mean_radiance)},
                               {"oldest_age", cache.oldest_age},
                               {"over_age_cells", cache.over_age_cells}};
      // The blend_lag signals, kept only when the check runs (the view's
      // luminance is also in the frame record, the view being a debug option).
      std::map<std::string, double> lag_signal = {{"output_luminance", output_luminance}};
      if (gi) {
        lag_signal["gi_luminance"] = gi_luminance;
        lag_signal["cache_mean_radiance"] = cache.mean_radiance;
      }
      if (scenario.cache_view) {
        lag_signal["cache_view_luminance"] = mean_luminance(renderer->cache_view());
        record["world_cache"]["view_mean_luminance"] = json_figure(lag_signal["cache_view_luminance"]);
      }
      if (cache_lifetime_check) cache_lifetime_check->record_frame(frame, cache);
      if (blend_lag)
        for (const auto& [name, value] : lag_signal) blend_lag_signals[name].values.push_back(value);
    }
    frame_log.add(record);
    if (hash_log) hash_log->add(state_hashes(frame));

    if (captures.count(frame)) {
      // Realtime: the halves are chains A and B of this frame (or A twice with one chain).
      const Image a = realtime ? realtime_frame(0) : renderer->reference_half(0);
      const Image b = realtime ? realtime_frame(renderer->di().settings().chains - 1) : renderer->reference_half(1);
      std::vector<Image> layers;
      const std::vector<std::string> names = {"albedo", "normal", "depth", "motion"};
      for (const std::string& n : names) layers.push_back(renderer->gbuffer_layer(n));
      std::vector<std::pair<std::string, const Image*>> exr = {{"", &last_mean}, {"half_a", &a}, {"half_b", &b}};
      const Image di_layer = realtime ? renderer->di().frame(0) : Image();
      const Image gi_layer = gi ? renderer->gi().gi_frame(0) : Image();
      const Image specular_layer = gi ? renderer->gi().specular_frame(0) : Image();
      if (realtime) exr.emplace_back("di", &di_layer);
      if (gi) {
        exr.emplace_back("gi", &gi_layer);
        exr.emplace_back("specular", &specular_layer);
      }
      const Image cache_view_layer = scenario.cache_view ? renderer->cache_view() : Image();
      if (scenario.cache_view) exr.emplace_back("cache_view", &cache_view_layer);
      for (std::size_t i = 0; i < names.size(); ++i) exr.emplace_back(names[i], &layers[i]);
      // Everything a replay needs to rebuild this run (replay/capture.h).
      nlohmann::json manifest = {
          {"frame", frame},
          {"frames", frames},
          {"seed", seed},
          {"scenario", {{"name", scenario.name}, {"file", scenario.file.string()}, {"document", scenario.raw}}},
          {"profile", scenario.profile},
          {"profile_option", options.profile ? nlohmann::json(*options.profile) : nlohmann::json(nullptr)},
          {"overrides", scenario.overrides},
          {"sets", options.sets},
          {"backend_request", options.backend},
          {"backend", gpu::backend_name(device.backend())},
          {"device_index", options.device ? nlohmann::json(*options.device) : nlohmann::json(nullptr)},
          {"device", device.info().to_json()},
          {"loop",
           {{"window_start", window_start},
            {"static_start", static_start},
            {"window_samples", window_samples},
            {"nonfinite_pixels_total", nonfinite_pixels_total},
            {"first_nonfinite_frame",
             first_nonfinite_frame ? nlohmann::json(*first_nonfinite_frame) : nlohmann::json(nullptr)},
            {"scene_hash", scene_hash(flat)}}}};
      write_capture(options.out_dir / capture_folder(frame), manifest, *renderer, exr, last_mean);
      capture_files.push_back(capture_images_file(frame).string());
      captured_frames.push_back(frame);
    }
    if (realtime_check && realtime_check->wants(frame)) {
      const gpu::DiPipeline& di = renderer->di();
      RealtimeEstimate estimate{realtime_frame(0), realtime_frame(1), realtime_mean(0), realtime_mean(1), window_start,
                                di.accumulated_frames(0)};
      estimate.full_gi = gi;
      realtime_check->compare_frame(frame, scene, estimate);
    }
    if (reference_check && reference_check->wants(frame)) {
      GpuEstimate estimate{last_mean, renderer->reference_half(0), renderer->reference_half(1), window_samples};
      reference_check->compare_frame(frame, scene, estimate);
    }
    if (!options.quiet && (frame + 1) % 16 == 0)
      spdlog::info("{}: frame {}/{}", scenario.name, frame + 1, frames);
  }

  if (realtime) {
    s_noise = {{"chain", renderer->di().settings().chains >= 2 ? realtime_noise(frames - 1) : nlohmann::json(nullptr)}};
    s_noise["temporal"] = {{"first_frame", temporal_noise.first_frame()},
                           {"frames", temporal_noise.frames()},
                           {"method", "per-pixel variance of chain A's signal over the frames of the window (the "
                                      "run's second half, restarted by scene changes) / (m^2 + 0.01), averaged; "
                                      "includes the world cache's own fluctuation, which the chain figures cancel"},
                           {"signals", temporal_noise.figures()}};
  }

  if (hash_log) {
    hash_log->finish();
    for (std::uint32_t f : captured_frames) attach_run_hashes(options.out_dir / capture_folder(f), hash_log->file());
  }
  RunResult result;
  if (determinism) result.checks.push_back(run_determinism_check(scenario, options, *determinism));
  if (reference_check) result.checks.push_back(reference_check->result());
  if (realtime_check) result.checks.push_back(realtime_check->result());
  if (cluster_ids_check) result.checks.push_back(cluster_ids_check->result());
  if (cache_lifetime_check) result.checks.push_back(cache_lifetime_check->result());
  if (jacobian_check) result.checks.push_back(jacobian_check->result());
  if (blend_lag) {
    std::vector<BlendLagSignal> curves;
    for (auto& [name, signal] : blend_lag_signals) curves.push_back({name, std::move(signal.values)});
    result.checks.push_back(judge_blend_lag(*blend_lag, lighting_event_frames(scenario), curves));
  }
  if (finite_check) {
    CheckResult c;
    c.name = "finite";
    c.figures = {{"nonfinite_samples", realtime ? 0 : renderer->reference_nonfinite_samples()},
                 {"nonfinite_pixels", nonfinite_pixels_total}};
    if (gi) c.figures["nonfinite_gi_reservoirs_and_output"] = gi_nonfinite_total;
    c.limits = {{"nonfinite", 0}};
    c.first_failing_frame = first_nonfinite_frame;
    c.verdict = first_nonfinite_frame ? Verdict::fail : Verdict::pass;
    c.message = first_nonfinite_frame ? fmt::format("non-finite values from frame {}", *first_nonfinite_frame)
                                      : "no NaN or inf in any sample or output pixel";
    result.checks.push_back(c);
  }
  const bool all_pass =
      std::all_of(result.checks.begin(), result.checks.end(), [](const CheckResult& c) { return c.passed(); });
  result.exit_code = all_pass ? 0 : 1;
  // Before the checks are written: it adds the captures to their evidence.
  nlohmann::json failure_captures = nlohmann::json::array();
  if (options.capture_failures && !all_pass && options.resume_from.empty()) {
    failure_captures = capture_failing_frames(scenario, options, frames, captured_frames, result.checks);
    for (const nlohmann::json& f : failure_captures)
      if (std::find(captured_frames.begin(), captured_frames.end(), f["frame"].get<std::uint32_t>()) ==
          captured_frames.end())
        capture_files.push_back(capture_images_file(f["frame"].get<std::uint32_t>()).string());
  }
  nlohmann::json checks = nlohmann::json::array();
  for (const CheckResult& c : result.checks) checks.push_back(c.to_json());

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
  s["noise"] = s_noise;
  if (renderer_options.world_cache) {
    // The cache's persistent cells at the end: equal across runs and thread counts.
    const gpu::WorldCache& cache = renderer->world_cache();
    auto hash = [](const auto& v) { return fmt::format("{:016x}", XXH3_64bits(v.data(), v.size() * sizeof(v[0]))); };
    s["world_cache_hashes"] = {{"checksums", hash(cache.checksums())},
                               {"life", hash(cache.life())},
                               {"radiance", hash(cache.radiance())},
                               {"root_frame", hash(cache.root_frames())}};
  }
  s["captures"] = capture_files;
  if (!skipped_captures.empty()) s["skipped_captures"] = skipped_captures;
  s["failure_captures"] = failure_captures;
  if (hash_log) s["hash_log"] = "buffer_hashes.jsonl";
  if (!options.resume_from.empty())
    s["resumed_from"] = {{"capture", options.resume_from.string()}, {"frame", first_frame - 1}};
  s["wall_seconds"] = json_figure(wall);
  write_json_file(options.out_dir / "summary.json", s);

  for (const CheckResult& c : result.checks)
    spdlog::log(c.passed() ? spdlog::level::info : spdlog::level::err, "{}: check {} {}: {}", scenario.name, c.name,
                to_string(c.verdict), c.message);
  return result;
}

}  // namespace gi
