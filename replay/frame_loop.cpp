#include "replay/frame_loop.h"

#include <chrono>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/cache_root.h"
#include "core/errors.h"
#include "core/phase_clock.h"
#include "core/metrics.h"
#include "replay/capture.h"
#include "core/scene_events.h"
#include "replay/resource_limits.h"
#include "replay/signal_figures.h"
#include "replay/test_faults.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {
// A capture's sub-folder with chain c's pipeline (c ≥ 1, RunSetup::chains).
std::string chain_folder(std::uint32_t c) { return fmt::format("chain_{}", c); }
}  // namespace

FrameLoop::FrameLoop(const Scenario& scenario, const RunOptions& options, RunSetup& setup, gpu::Device& device)
    : scenario_(scenario), options_(options), setup_(setup), device_(device), compiler_(cache_root()),
      scene_(setup.initial), geometry_(std::move(setup.geometry)), frame_log_(options.out_dir / "frames.jsonl") {
  const PhaseScope timed(phase::kGpuSetup);
  if (setup.record_hashes) hash_log_.emplace(options.out_dir / "buffer_hashes.jsonl");
  build_renderer();
  previous_camera_ = make_gpu_camera(scene_.camera, setup.width, setup.height);
  if (!options.resume_from.empty()) resume();
}

void FrameLoop::build_renderer() {
  renderer_.reset();  // one pipeline's buffers at a time
  other_chains_.clear();
  // On a CPU device every pass time is compared as a multiple of the
  // calibration kernel's (reports/timing_verdict.h); a GPU's are compared in ms.
  setup_.renderer_options.timing_calibration = device_.info().device_type == "cpu";
  renderer_ = std::make_unique<gpu::Renderer>(device_, compiler_, geometry_, setup_.renderer_options);
  gpu::RendererOptions other = setup_.renderer_options;
  other.timing_calibration = false;  // their passes are not timed against anything
  for (std::uint32_t c = 1; c < setup_.chains; ++c)
    other_chains_.push_back(std::make_unique<gpu::Renderer>(device_, compiler_, geometry_, other));
  for (auto& check : setup_.checks) check->prepare(*renderer_, scene_, geometry_);
  upload_scene();
}

// The renderer's scene is scene_ except where a profile re-creates a bug in
// what Bevy extracts: before v0.19.1 (#24764, cd0f5f628d) Solari never took
// an entity whose RaytracingMesh3d was removed out of its ray-traced scene.
// scene_ stays the truth the checks and references see.
void FrameLoop::upload_scene() {
  std::vector<std::size_t> kept;
  if (setup_.settings.raytracing_mesh_removal_ignored)
    for (std::size_t i = 0; i < scene_.instances.size(); ++i)
      if (scene_.instances[i].raytracing_mesh_removed && !scene_.instances[i].visible) kept.push_back(i);
  for (std::size_t i : kept) scene_.instances[i].visible = true;
  flat_ = flatten_instances(scene_, geometry_);
  each_pipeline([&](gpu::Renderer& r) { r.update_scene(flat_, scene_.visible_instances()); });
  for (std::size_t i : kept) scene_.instances[i].visible = false;
}

nlohmann::json FrameLoop::restored_state_hashes(std::uint32_t frame) {
  gpu::StateList state;
  renderer_->list_state(state);
  return hash_record(frame, state, renderer_->hash_buffers(state_ranges(state)));
}

// Replay: the scene at the captured frame (events are a pure function of the
// frame), the pipeline rebuilt for it, its state, the loop's and the checks' restored.
void FrameLoop::resume() {
  const Capture capture = read_capture(options_.resume_from);
  const std::string manifest = (capture.dir / "manifest.json").string();
  if (capture.frame + 1 >= setup_.frames)
    throw InputError(manifest, "/frame", fmt::format("a frame before the run's last ({} frames)", setup_.frames));
  scene_ = scene_at_frame(setup_.initial, scenario_, capture.frame);
  geometry_ = flatten_geometry(scene_);
  build_renderer();
  restore_capture(capture, *renderer_);
  for (std::uint32_t c = 1; c < setup_.chains; ++c) {
    const std::filesystem::path dir = capture.dir / chain_folder(c);
    if (!std::filesystem::exists(dir / "manifest.json"))
      throw InputError(manifest, "/buffers",
                       fmt::format("chain {}'s state in {} (this run has {} independent chains)", c, dir.string(),
                                   setup_.chains));
    restore_capture(read_capture(dir), *other_chains_[c - 1]);
  }
  const nlohmann::json& loop = capture.manifest["loop"];
  if (loop.value("scene_hash", "") != scene_hash(flat_))
    spdlog::warn("{}: the scene re-derived at frame {} differs from the captured one (scenario or code changed?)",
                 manifest, capture.frame);
  window_start_ = loop.value("window_start", 0u);
  static_start_ = loop.value("static_start", window_start_);
  window_samples_ = loop.value("window_samples", std::uint64_t{0});
  const nlohmann::json& states = loop.contains("checks") ? loop["checks"] : nlohmann::json::object();
  for (std::size_t i = 0; i < setup_.checks.size(); ++i)
    if (states.contains(scenario_.checks[i].name)) setup_.checks[i]->restore_state(states[scenario_.checks[i].name]);
  previous_camera_ = make_gpu_camera(scene_.camera, setup_.width, setup_.height);
  nlohmann::json restored = restored_state_hashes(capture.frame);
  restored["restored"] = true;  // the state as restored, before any replayed frame
  hash_log_->add(restored);
  first_frame_ = capture.frame + 1;
}

// Spawns update the acceleration structures and scene buffers in place:
// reservoirs, the world cache and every other pass's history carry on
// (Bevy's Solari keeps them across scene changes). Only a spawned generated
// mesh changes the flat geometry; meshes are only appended. Any change
// starts a new accumulation window (the reference mode estimates one static
// image); a realtime reference check with warmup_frames starts its window
// that many frames into the static window.
void FrameLoop::apply_frame_events(std::uint32_t frame) {
  const ChangeSet changes = apply_events(scene_, setup_.initial, scenario_, frame);
  if (changes.geometry) check_resource_limits(scenario_, scene_, device_.largest_heap_bytes(), device_.limits().maxStorageBufferRange);
  if (changes.geometry && scene_.meshes.size() != geometry_.meshes.size()) {
    geometry_ = flatten_geometry(scene_);
    each_pipeline([&](gpu::Renderer& r) { r.update_geometry(geometry_); });
    for (auto& check : setup_.checks) check->prepare(*renderer_, scene_, geometry_);
  }
  if (changes.any()) {
    upload_scene();
  } else if (changes.motion) {  // the frame after a move: last frame's transforms only
    for (std::size_t i = 0; i < scene_.instances.size(); ++i)
      flat_.previous_object_to_world[i] = scene_.instances[i].previous_transform.value_or(scene_.instances[i].transform);
    each_pipeline([&](gpu::Renderer& r) { r.update_previous_transforms(flat_); });
  }
  if (changes.any() && frame > 0) static_start_ = frame;
  const std::uint32_t warmup = setup_.warmup_frames;
  if ((changes.any() && frame > 0) || (warmup > 0 && frame == static_start_ + warmup)) {
    each_pipeline([](gpu::Renderer& r) { r.reset_accumulation(); });
    window_samples_ = 0;
    window_start_ = frame;
  }
  // The temporal noise window: the second half of the run, restarted by any change.
  if (setup_.realtime && (frame == noise_start() || (changes.any() && frame > noise_start()))) {
    temporal_noise_.restart(frame);
    each_pipeline([](gpu::Renderer& r) { r.frame_output().restart_noise(); });
  }
}

// What the frame record and the checks read of every frame: a few dozen
// bytes the GPU reduced, taken as soon as the frame's submission finished
// (the output image is read back only if a check asks for it this frame).
FrameLoop::Taken FrameLoop::take(std::uint32_t frame, std::chrono::steady_clock::time_point started,
                                 const gpu::Device::TransferCounts& before) {
  Taken t;
  t.frame = frame;
  t.started = started;
  t.window_start = window_start_;
  t.window_samples = window_samples_;
  t.timings = renderer_->last_timings();
  t.calibration_ms = renderer_->last_calibration_ms();
  t.measures = renderer_->frame_output().measures();
  if (!setup_.realtime) t.nonfinite_samples = renderer_->reference_nonfinite_samples();
  if (setup_.gi) t.gi_stats = renderer_->gi().stats();
  if (setup_.renderer_options.world_cache) t.cache_stats = renderer_->world_cache().stats();
  if (hashes_state(frame)) t.state_hashes = renderer_->frame_hashes();
  const gpu::Device::TransferCounts& now = device_.transfers();
  t.transfers = {now.downloaded - before.downloaded, now.uploaded - before.uploaded, now.downloads - before.downloads,
                 now.uploads - before.uploads};
  return t;
}

const Image& FrameLoop::read_output() {
  if (!output_read_) output_ = renderer_->frame_output().image();
  output_read_ = true;
  return output_;
}

bool FrameLoop::logs_hashes(std::uint32_t frame) const { return hash_log_ && frame >= setup_.hash_log_from; }

bool FrameLoop::hashes_state(std::uint32_t frame) const { return logs_hashes(frame) || frame + 1 == setup_.frames; }

// Frame f's observation may wait until frame f + 1 is on the GPU when it
// reads only what take() kept: no check judging f reads a buffer, no
// capture, not the last frame, no cache view to read back, and frame f + 1
// changes nothing (its events would reach the scene and the checks'
// prepare() before they observed f).
bool FrameLoop::can_defer(std::uint32_t frame) const {
  if (frame + 1 >= setup_.frames || setup_.captures.count(frame) || scenario_.cache_view) return false;
  static const std::set<FrameInput> kept = {FrameInput::output, FrameInput::gi_stats, FrameInput::gi_luminance,
                                            FrameInput::cache_stats, FrameInput::nonfinite_samples};
  for (const CheckNeeds& needs : setup_.needs) {
    if (needs.frames && !needs.frames->count(frame)) continue;
    for (FrameInput input : needs.reads)
      if (!kept.count(input)) return false;
  }
  return !changes_at(scene_, setup_.initial, scenario_, frame + 1).any();
}

// The frame's record and the checks' look at it, from what take() kept
// (frames not deferred may also read buffers: the GPU is idle then).
void FrameLoop::observe(const Taken& t, bool deferred) {
  const std::uint32_t frame = t.frame;
  const gpu::Device::TransferCounts before = device_.transfers();
  FrameData data;
  data.frame = frame;
  data.scene = &scene_;
  data.renderer = renderer_.get();
  for (std::uint32_t c = 0; c < setup_.chains; ++c) data.chains.push_back(&chain_pipeline(c));
  data.window_start = t.window_start;
  data.window_samples = t.window_samples;
  output_read_ = false;
  if (!deferred) data.read_output = [this]() -> const Image& { return read_output(); };
  data.output_luminance = t.measures.output_luminance;
  data.nonfinite_pixels = t.measures.nonfinite_components;
  data.nonfinite_samples = t.nonfinite_samples;
  data.gi_luminance = t.measures.gi_luminance;
  frame_image_hashes_.push_back(t.measures.image_hash);

  nlohmann::json timings = nlohmann::json::object();
  for (const auto& pass : t.timings) timings[pass.name] = json_figure(pass.ms);
  nlohmann::json record = {{"frame", frame},
                           {"window_start", t.window_start},
                           {"window_samples", t.window_samples},
                           {"mean_luminance", json_figure(data.output_luminance)},
                           {"nonfinite_pixels", data.nonfinite_pixels},
                           {"nonfinite_samples", t.nonfinite_samples},
                           {"pass_ms", timings}};
  if (setup_.renderer_options.timing_calibration) {
    record["calibration_ms"] = json_figure(t.calibration_ms);
    if (t.cpu.available)
      record["cpu_schedule"] = {{"run_ms", json_figure(double(t.cpu.run_ns) * 1e-6)},
                                {"wait_ms", json_figure(double(t.cpu.wait_ns) * 1e-6)}};
  }
  if (setup_.realtime) {
    record["signal_mean_luminance"] = {{"di", json_figure(t.measures.di_luminance)}};
    if (setup_.gi) {
      record["signal_mean_luminance"]["gi"] = json_figure(t.measures.gi_luminance);
      record["signal_mean_luminance"]["specular"] = json_figure(t.measures.specular_luminance);
    }
  }
  if (t.gi_stats) {
    data.gi_stats = &*t.gi_stats;
    record["gi"] = {{"merges", t.gi_stats->merges},
                    {"rejections", t.gi_stats->rejections},
                    {"max_accepted_j", json_figure(t.gi_stats->max_accepted_j)},
                    {"nonfinite_reservoirs", t.gi_stats->nonfinite_reservoirs},
                    {"nonfinite_output", t.gi_stats->nonfinite_output}};
  }
  if (t.cache_stats) {
    data.cache_stats = &*t.cache_stats;
    record["world_cache"] = {{"active_cells", t.cache_stats->active_cells},
                             {"updated_cells", t.cache_stats->updated_cells},
                             {"live_cells", t.cache_stats->live_cells},
                             {"mean_radiance", json_figure(t.cache_stats->mean_radiance)},
                             {"oldest_age", t.cache_stats->oldest_age},
                             {"over_age_cells", t.cache_stats->over_age_cells}};
    if (scenario_.cache_view) {  // never deferred (can_defer)
      data.cache_view_luminance = mean_luminance(renderer_->cache_view());
      record["world_cache"]["view_mean_luminance"] = json_figure(*data.cache_view_luminance);
    }
  }
  for (std::size_t i = 0; i < setup_.checks.size(); ++i) {
    const CheckNeeds& needs = setup_.needs[i];
    if (!needs.frames || needs.frames->count(frame)) setup_.checks[i]->observe(FrameView(data, needs.reads), record);
  }
  // What observing this frame moved: its rendering's small results (take)
  // and the record's and the checks' readbacks; state hashes and captures
  // come after. Whether its record waited for the next frame's submission.
  const gpu::Device::TransferCounts& now = device_.transfers();
  record["transfers"] = {{"downloaded_bytes", t.transfers.downloaded + now.downloaded - before.downloaded},
                         {"downloads", t.transfers.downloads + now.downloads - before.downloads},
                         {"uploaded_bytes", t.transfers.uploaded + now.uploaded - before.uploaded}};
  record["observed_during_next_frame"] = deferred;
  frame_log_.add(record);
  const bool last = frame + 1 == setup_.frames;
  if (last) read_output();  // the run's final image (summary, baseline)
  if (hashes_state(frame)) {
    gpu::StateList state;
    renderer_->list_state(state);
    const nlohmann::json hashes = hash_record(frame, state, t.state_hashes);
    if (logs_hashes(frame)) hash_log_->add(hashes);
    if (last)
      for (const nlohmann::json& b : hashes["buffers"]) final_state_hashes_[b[0].get<std::string>()] = b[1];
  }
  if (setup_.captures.count(frame)) capture(frame);
  if (!options_.quiet && (frame + 1) % 16 == 0) spdlog::info("{}: frame {}/{}", scenario_.name, frame + 1, setup_.frames);
}

// Per frame: events, then the frame's submission; while the GPU renders it,
// the previous frame's observation if it was deferred; then the wait, what
// the frame record needs taken at once, and its observation, now or, when
// can_defer allows, during the next frame's rendering. The GPU then waits
// for the host only for events, recording and the frames that read buffers.
void FrameLoop::run() {
  const PhaseScope timed(phase::kFrames);
  const std::uint32_t width = setup_.width, height = setup_.height;
  std::optional<Taken> deferred;
  // On a CPU device the passes run on this process's threads: how long they
  // waited for a CPU says how loaded the machine was (core/cpu_schedule.h).
  const bool cpu_timed = setup_.renderer_options.timing_calibration;
  for (std::uint32_t frame = first_frame_; frame < setup_.frames; ++frame) {
    const auto started = std::chrono::steady_clock::now();
    inject_test_fault(scenario_.name, frame);
    const gpu::Device::TransferCounts transfers_before = device_.transfers();
    apply_frame_events(frame);
    const GpuCamera camera = make_gpu_camera(scene_.camera, width, height);
    const bool noise_frame = setup_.realtime && frame >= noise_start();
    if (setup_.realtime) each_pipeline([&](gpu::Renderer& r) { r.frame_output().set_accumulate_noise(noise_frame); });
    if (noise_frame) temporal_noise_.count_frame();
    if (hashes_state(frame)) {  // the state hashed at the end of the frame, in its submission
      gpu::StateList state;
      renderer_->list_state(state);
      renderer_->hash_after_next_frame(state_ranges(state));
    }
    const CpuSchedule cpu_before = cpu_timed ? cpu_schedule_now() : CpuSchedule{};
    const GpuCamera previous = frame == 0 ? camera : previous_camera_;
    renderer_->submit_frame(
        frame_constants(camera, previous, flat_, width, height, frame, setup_.seed, scenario_.samples_per_frame));
    previous_camera_ = camera;
    window_samples_ += scenario_.samples_per_frame;
    if (deferred) {
      observe(*deferred, true);
      frame_wall_ms_.push_back(since_ms(deferred->started, started));
      deferred.reset();
    }
    renderer_->finish_frame();
    // The other chains after chain A (one submission in flight at a time);
    // take() reads chain A's timings and results only.
    for (std::uint32_t c = 1; c < setup_.chains; ++c)
      other_chains_[c - 1]->render_frame(frame_constants(camera, previous, flat_, width, height, frame,
                                                          independent_chain_seed(setup_.seed, c),
                                                          scenario_.samples_per_frame));
    Taken t = take(frame, started, transfers_before);
    if (cpu_timed) t.cpu = cpu_schedule_between(cpu_before, cpu_schedule_now());
    if (can_defer(frame)) {
      deferred = std::move(t);
    } else {
      observe(t, false);
      frame_wall_ms_.push_back(since_ms(started, std::chrono::steady_clock::now()));
    }
  }
  if (setup_.realtime) {
    noise_ = {{"chain", setup_.chains >= 2 ? chain_noise_figures(setup_.frames - 1) : nlohmann::json(nullptr)}};
    noise_["temporal"] = {{"first_frame", temporal_noise_.first_frame()},
                          {"frames", temporal_noise_.frames()},
                          {"method", "per-pixel variance of chain A's signal over the frames of the window (the "
                                     "run's second half, restarted by scene changes) / (m^2 + 0.01), averaged; "
                                     "includes the world cache's own fluctuation"},
                          {"signals", temporal_noise_.figures(renderer_->frame_output().noise_sums())}};
  }
  if (hash_log_) {
    hash_log_->finish();
    for (std::uint32_t f : captured_frames_) attach_run_hashes(options_.out_dir / capture_folder(f), hash_log_->file());
  }
}

// Each signal's per-frame noise at `frame`, from chains A and B
// (chain_noise), relative to the temporal mean of the whole output, so the
// signals' figures are on one scale.
nlohmann::json FrameLoop::chain_noise_figures(std::uint32_t frame) const {
  Image mean = chain_pipeline(0).realtime_mean(0);
  const Image mean_b = chain_pipeline(1).realtime_mean(0);
  for (std::size_t i = 0; i < mean.pixels.size(); ++i) mean.pixels[i] = 0.5f * (mean.pixels[i] + mean_b.pixels[i]);
  // Each chain's signals, read back once.
  std::map<std::string, Image> a, b;
  for (auto [chain, out] : {std::pair{0u, &a}, std::pair{1u, &b}}) {
    const gpu::Renderer& r = chain_pipeline(chain);
    (*out)["di"] = r.di().frame(0);
    (*out)["output"] = (*out)["di"];
    if (setup_.gi) {
      (*out)["gi"] = r.gi().gi_frame(0);
      (*out)["specular"] = r.gi().specular_frame(0);
      (*out)["output"] = sum_images(sum_images((*out)["output"], (*out)["gi"]), (*out)["specular"]);
    }
  }
  nlohmann::json signals = nlohmann::json::object();
  for (const auto& [name, image] : a) signals[name] = json_figure(chain_noise(image, b.at(name), mean));
  nlohmann::json additivity = nullptr;
  if (setup_.gi) {
    const NoiseAdditivity add = chain_noise_additivity({a["di"], a["gi"], a["specular"]},
                                                       {b["di"], b["gi"], b["specular"]}, mean);
    additivity = {{"output", json_figure(add.output)},
                  {"sum_of_signals", json_figure(add.sum_of_signals)},
                  {"cross_term", json_figure(add.cross_term)},
                  {"cross_term_standard_error", json_figure(add.cross_term_standard_error)},
                  {"method", "output = sum of the signals' figures + the cross term mean((sum of the signals' "
                             "A - B products over pairs) / (m^2 + 0.01)); standard error from its 8x8-pixel "
                             "block means"}};
  }
  return nlohmann::json{{"frame", frame},
                        {"additivity", additivity},
                        {"method", "per-frame relMSE of one chain against its expectation: mean over pixels and "
                                   "channels of (A - B)^2 / 2 / (m^2 + 0.01), A and B the two chains' signal at "
                                   "this frame, m the temporal mean of the output (both chains)"},
                        {"signals", signals}};
}

// Everything a replay needs to rebuild this run (replay/capture.h).
void FrameLoop::capture(std::uint32_t frame) {
  const gpu::Renderer& r = *renderer_;
  // Realtime: the halves are chains A and B of this frame (or A twice with one chain).
  const Image a = setup_.realtime ? r.realtime_frame(0) : r.reference_half(0);
  const Image b = setup_.realtime ? chain_pipeline(setup_.chains > 1 ? 1 : 0).realtime_frame(0) : r.reference_half(1);
  // Chain A's signals, read back for the capture only.
  read_output();
  const Image di = setup_.realtime ? r.di().frame(0) : Image();
  const Image gi = setup_.gi ? r.gi().gi_frame(0) : Image();
  const Image specular = setup_.gi ? r.gi().specular_frame(0) : Image();
  std::vector<Image> layers;
  const std::vector<std::string> names = {"albedo", "normal", "depth", "motion"};
  for (const std::string& n : names) layers.push_back(r.gbuffer_layer(n));
  std::vector<std::pair<std::string, const Image*>> exr = {{"", &output_}, {"half_a", &a}, {"half_b", &b}};
  if (setup_.realtime) exr.emplace_back("di", &di);
  if (setup_.gi) {
    exr.emplace_back("gi", &gi);
    exr.emplace_back("specular", &specular);
  }
  const Image cache_view_layer = scenario_.cache_view ? r.cache_view() : Image();
  if (scenario_.cache_view) exr.emplace_back("cache_view", &cache_view_layer);
  for (std::size_t i = 0; i < names.size(); ++i) exr.emplace_back(names[i], &layers[i]);
  nlohmann::json check_states = nlohmann::json::object();
  for (std::size_t i = 0; i < setup_.checks.size(); ++i)
    if (nlohmann::json s = setup_.checks[i]->saved_state(); !s.is_null()) check_states[scenario_.checks[i].name] = s;
  const RunOptions& o = options_;
  nlohmann::json manifest = {
      {"frame", frame},
      {"frames", setup_.frames},
      {"seed", setup_.seed},
      {"scenario", {{"name", scenario_.name}, {"file", scenario_.file.string()}, {"document", scenario_.raw}}},
      {"profile", scenario_.profile},
      {"profile_option", o.profile ? nlohmann::json(*o.profile) : nlohmann::json(nullptr)},
      {"overrides", scenario_.overrides},
      {"sets", o.sets},
      {"backend_request", o.backend},
      {"backend", gpu::backend_name(device_.backend())},
      {"device_index", o.device ? nlohmann::json(*o.device) : nlohmann::json(nullptr)},
      {"device", device_.info().to_json()},
      {"loop",
       {{"window_start", window_start_},
        {"static_start", static_start_},
        {"window_samples", window_samples_},
        {"checks", check_states},
        {"scene_hash", scene_hash(flat_)}}}};
  write_capture(o.out_dir / capture_folder(frame), manifest, *renderer_, exr, output_);
  // The other chains' pipeline state, so a replay's checks see every chain as the run did.
  for (std::uint32_t c = 1; c < setup_.chains; ++c) {
    manifest["seed"] = independent_chain_seed(setup_.seed, c);
    const Image image = other_chains_[c - 1]->realtime_frame(0);
    write_capture(o.out_dir / capture_folder(frame) / chain_folder(c), manifest, *other_chains_[c - 1],
                  {{"", &image}}, image);
  }
  captured_frames_.push_back(frame);
}

}  // namespace gi
