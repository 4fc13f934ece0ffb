#include "replay/run_summary.h"

#include <map>

#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/exr_io.h"
#include "core/shared/word_hash.h"
#include "reports/change.h"
#include "replay/capture.h"
#include "reports/json_figures.h"
#include "reports/summary.h"
#include "replay/equal_time.h"
#include "core/scene_events.h"
#include "core/reference/reference_cache.h"
#include "core/cache_root.h"
#include "core/phase_clock.h"
#include "replay/signal_figures.h"
#include "replay/wall_breakdown.h"

namespace gi {

// Beside the passes: each frame's GPU pass sum (all passes; the pipeline's
// alone) and its host wall time, and the ratio of their medians (the observation target
// "wall ≤ 1.25× the GPU pass sum").
void add_frames(FrameLog& log, const std::vector<double>& frame_wall_ms, nlohmann::json& s) {
  const nlohmann::json kept = log.kept();
  std::map<std::string, std::vector<double>> pass_ms;
  std::vector<double> pass_sum_ms, pipeline_sum_ms;
  for (const nlohmann::json& f : kept) {
    double sum = 0, pipeline = 0;
    for (const auto& [name, ms] : f["pass_ms"].items()) {
      if (!ms.is_number()) continue;
      pass_ms[name].push_back(ms.get<double>());
      sum += ms.get<double>();
      if (!observation_pass(name)) pipeline += ms.get<double>();
    }
    pass_sum_ms.push_back(sum);
    pipeline_sum_ms.push_back(pipeline);
  }
  s["timings"] = timing_summary(pass_ms);
  // The calibration kernel's time per frame (CPU devices): the unit the
  // nightly's timing verdicts compare passes in (reports/timing_verdict.h).
  std::vector<double> calibration_ms;
  for (const nlohmann::json& f : kept)
    if (f.contains("calibration_ms") && f["calibration_ms"].is_number()) calibration_ms.push_back(f["calibration_ms"]);
  if (!calibration_ms.empty())
    s["timings"]["calibration"] = {{"frames", calibration_ms.size()},
                                   {"median_ms", json_figure(percentile(calibration_ms, 0.5))},
                                   {"p95_ms", json_figure(percentile(calibration_ms, 0.95))}};
  if (!pass_sum_ms.empty() && !frame_wall_ms.empty()) {
    const double gpu = percentile(pass_sum_ms, 0.5), wall = percentile(frame_wall_ms, 0.5);
    s["timings"]["frame"] = {{"gpu_pass_sum_median_ms", json_figure(gpu)},
                             {"pipeline_pass_sum_median_ms", json_figure(percentile(pipeline_sum_ms, 0.5))},
                             {"wall_median_ms", json_figure(wall)},
                             {"wall_p95_ms", json_figure(percentile(frame_wall_ms, 0.95))},
                             {"wall_over_gpu", json_figure(gpu > 0 ? wall / gpu : 0.0)},
                             {"frames", frame_wall_ms.size()}};
  }
  s["frames"] = kept;
  log.finish();
  s["frames_log"] = {{"file", "frames.jsonl"}, {"records", log.count()}, {"kept_every", log.stride()}};
}

namespace {

// DI, GI and specular each: per-frame noise (the chains), bias against the
// Embree reference of the same quantity (replay/signal_figures.h) over the
// window that ends at the run's last frame, and ms.
nlohmann::json per_signal_figures(const RunFacts& run, const nlohmann::json& s, const Scene& scene,
                                  const ReferenceOptions& options, const ReferenceResult& reference) {
  const gpu::Renderer& r = run.loop.renderer();
  const gpu::Renderer& b = run.loop.chain_pipeline(1);  // a check with two chains made this run's summary ask
  const nlohmann::json noise = s.value("noise", nlohmann::json::object());
  const nlohmann::json ms = signal_ms(s["timings"], s["resolved"].value("chains", 1u));
  auto noise_of = [&](const char* kind, const std::string& signal) {
    const nlohmann::json k = noise.is_object() ? noise.value(kind, nlohmann::json(nullptr)) : nlohmann::json(nullptr);
    return k.is_object() && k.contains("signals") ? k["signals"].value(signal, nlohmann::json(nullptr))
                                                 : nlohmann::json(nullptr);
  };
  nlohmann::json out = nlohmann::json::object();
  for (const char* signal : {"di", "gi", "specular"}) {
    if (!run.setup.gi && std::string(signal) != "di") continue;
    out[signal] = {{"noise_chain", noise_of("chain", signal)},
                   {"noise_temporal", noise_of("temporal", signal)},
                   {"ms", ms.value(signal, nlohmann::json(nullptr))},
                   {"bias", nullptr}};
  }
  out["shared_ms"] = ms.value("shared", nlohmann::json(nullptr));
  // The DI reference: the check's own without GI, else Embree's direct mode.
  ReferenceOptions direct_options = options;
  direct_options.direct_only = true;
  const ReferenceResult direct =
      options.direct_only ? reference : cached_reference(scene, direct_options, cache_root() / "reference");
  const ChainMeans di{r.di().mean(0), b.di().mean(0)};
  out["di"]["bias"] = signal_bias(di, direct.mean, direct.half_a, direct.half_b);
  if (run.setup.gi) {
    const ReferenceResult indirect = indirect_reference(reference, direct);
    ChainMeans both{sum_images(r.gi().gi_mean(0), r.gi().specular_mean(0)),
                    sum_images(b.gi().gi_mean(0), b.gi().specular_mean(0))};
    out["indirect"] = {{"signals", {"gi", "specular"}},
                       {"bias", signal_bias(both, indirect.mean, indirect.half_a, indirect.half_b)},
                       {"reference", "Embree full minus Embree direct, halves minus halves"}};
  }
  return out;
}

// The realtime output's last frame judged by the `reference` check beside the
// equal-time path tracers (replay/equal_time.h), with its reference (cached by
// the check) and the scene of that frame; null without such a frame.
nlohmann::json run_equal_time(const RunFacts& run, const nlohmann::json& s, const std::vector<CheckResult>& checks) {
  const RunSetup& setup = run.setup;
  for (const CheckResult& c : checks) {
    if (c.name != "reference" || !c.figures.contains("frames") || c.figures["frames"].empty()) continue;
    const nlohmann::json& last = c.figures["frames"].back();
    if (!last.contains("per_frame") || !last.contains("temporal_mean")) continue;
    const std::uint32_t frame = last["frame"].get<std::uint32_t>();
    const Scene scene = scene_at_frame(setup.initial, run.scenario, frame);
    EqualTimeTarget t;
    t.scene = &scene;
    t.reference_options.width = setup.width;
    t.reference_options.height = setup.height;
    t.reference_options.spp = c.limits["reference_spp"].get<std::uint32_t>();
    t.reference_options.seed = setup.seed;
    t.reference_options.direct_only = !setup.gi;
    const ReferenceResult reference = cached_reference(scene, t.reference_options, cache_root() / "reference");
    t.reference = &reference;
    // One chain's cost: the run renders two (the check's noise estimate), a
    // shipped pipeline one, and the realtime error is one chain's.
    t.realtime.ms_per_frame = one_chain_ms_per_frame(s["timings"], s["resolved"].value("chains", 1u));
    t.realtime.frame_relmse = last["per_frame"]["relmse"].get<double>();
    t.realtime.temporal_relmse = last["temporal_mean"]["relmse"].get<double>();
    t.realtime.window_frames = last["window_frames"].get<std::uint32_t>();
    nlohmann::json out = equal_time_figures(&run.device, &run.loop.compiler(), t);
    out["frame"] = frame;
    // The signals' temporal means are the window's that ends at the run's last frame.
    if (frame + 1 == setup.frames) out["signals"] = per_signal_figures(run, s, scene, t.reference_options, reference);
    return out;
  }
  return nullptr;
}

}  // namespace

void write_run_summary(const RunFacts& run, const nlohmann::json& failure_captures, RunResult& result) {
  std::optional<PhaseScope> timed(std::in_place, phase::kSummary);  // ends before the breakdown is taken
  const Scenario& scenario = run.scenario;
  const RunSetup& setup = run.setup;
  nlohmann::json checks = nlohmann::json::array();
  for (const CheckResult& c : result.checks) checks.push_back(c.to_json());

  nlohmann::json& s = result.summary;
  s["schema_version"] = 1;
  s["scenario"] = {{"name", scenario.name}, {"file", scenario.file.string()}, {"document", scenario.raw}};
  s["resolved"] = {{"resolution", {setup.width, setup.height}},
                   {"frames", setup.frames},
                   {"seed", setup.seed},
                   {"profile", scenario.profile},
                   {"overrides", scenario.overrides},
                   {"mode", setup.realtime ? "realtime" : "reference"},
                   {"profile_values", setup.profile.to_json()},
                   {"samples_per_frame", scenario.samples_per_frame},
                   {"chains", setup.renderer_options.di ? setup.renderer_options.di->chains : 0u},
                   {"independent_chains", setup.chains},
                   {"backend", gpu::backend_name(run.device.backend())}};
  s["scene"] = {{"name", setup.initial.name},
                {"instances", setup.initial.instances.size()},
                {"triangles", setup.initial.triangle_count()},
                {"lights", run.loop.light_count()},
                {"warnings", setup.initial.warnings}};
  s["device"] = run.device.info().to_json();
  s["build"] = build_info();
  s["verdict"] = result.exit_code == 0 ? "pass" : "fail";
  s["exit_code"] = result.exit_code;
  s["checks"] = checks;
  add_frames(run.loop.frame_log(), run.loop.frame_wall_ms(), s);
  const Image& last = run.loop.last_output();
  s["final_image_hash"] = bytes_hash(last.pixels.data(), last.pixels.size() * sizeof(glm::vec3));
  // What a baseline keeps to report any change exactly (reports/change.h):
  // the image hash per frame, every state buffer's hash after the last frame,
  // and the final image (half-float EXR: a baseline stores it, and the
  // comparison then reads both sides at the same precision).
  s["hashes"] = {{"scheme", shader::WORD_HASH_SCHEME},
                 {"first_frame", run.loop.first_frame()},
                 {"frame_images", run.loop.frame_image_hashes()},
                 {"final_buffers", run.loop.final_state_hashes()}};
  write_exr(run.options.out_dir / kFinalImageFile, {{"", &last}}, ExrPixels::half);
  s["final_image"] = kFinalImageFile;
  s["noise"] = run.loop.noise();
  if (run.options.equal_time && setup.realtime) {
    const PhaseScope timed_peers(phase::kEqualTime);
    s["equal_time"] = run_equal_time(run, s, result.checks);
  }
  // The reference cache's entries this run read or rendered: what `nightly
  // --update-baseline` keeps as seeds (core/reference/reference_cache.h).
  const std::vector<std::string> used = reference_entries_used();
  s["reference_entries"] = std::vector<std::string>(used.begin() + std::ptrdiff_t(std::min(run.references_at_start, used.size())), used.end());
  if (setup.renderer_options.world_cache) {
    // The cache's persistent cells at the end: equal across runs and thread counts.
    const gpu::WorldCache& cache = run.loop.renderer().world_cache();
    auto hash = [](const auto& v) { return bytes_hash(v.data(), v.size() * sizeof(v[0])); };
    s["world_cache_hashes"] = {{"checksums", hash(cache.checksums())},
                               {"life", hash(cache.life())},
                               {"radiance", hash(cache.radiance())},
                               {"root_frame", hash(cache.root_frames())}};
  }
  nlohmann::json captures = nlohmann::json::array();
  for (std::uint32_t f : run.loop.captured_frames()) captures.push_back(capture_images_file(f).string());
  for (const nlohmann::json& f : failure_captures) {
    const nlohmann::json file = capture_images_file(f["frame"].get<std::uint32_t>()).string();
    if (std::find(captures.begin(), captures.end(), file) == captures.end()) captures.push_back(file);
  }
  s["captures"] = captures;
  if (!setup.skipped_captures.empty()) s["skipped_captures"] = setup.skipped_captures;
  s["failure_captures"] = failure_captures;
  if (run.loop.hash_log_written()) s["hash_log"] = "buffer_hashes.jsonl";
  if (!run.options.resume_from.empty())
    s["resumed_from"] = {{"capture", run.options.resume_from.string()}, {"frame", run.loop.first_frame() - 1}};
  timed.reset();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - run.started).count();
  s["wall_seconds"] = json_figure(wall);
  s["wall_breakdown"] = wall_breakdown(wall, s["frames"], run.phases_at_start);
  write_json_file(run.options.out_dir / "summary.json", s);
  spdlog::info("{}: {}", scenario.name, wall_breakdown_line(s["wall_breakdown"]));
}

}  // namespace gi
