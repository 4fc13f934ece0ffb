#include "replay/equal_time.h"

#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "core/metrics.h"
#include "core/scene_flatten.h"
#include "core/shared/rng.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

constexpr std::uint32_t kCalibrationSpp = 16;

// The GPU reference path tracer alone (no G-buffer, no realtime passes) over
// one scene state: each render starts afresh and takes its spp in one frame.
class GpuPathTracer {
 public:
  GpuPathTracer(gpu::Device& device, gpu::ShaderCompiler& compiler, const Scene& scene, const ReferenceOptions& o)
      : geometry_(flatten_geometry(scene)),
        flat_(flatten_instances(scene, geometry_)),
        camera_(make_gpu_camera(scene.camera, o.width, o.height)),
        options_(o),
        renderer_(device, compiler, geometry_, renderer_options(scene, o)) {
    renderer_.update_scene(flat_, scene.visible_instances());
  }
  // GPU ms of the path tracing pass for `spp` samples from `first_sample` on.
  double render(std::uint32_t spp, std::uint32_t first_sample) {
    renderer_.reset_accumulation();
    FrameConstants c = frame_constants(camera_, camera_, flat_, options_.width, options_.height, 0, options_.seed, spp);
    c.counts.w = first_sample;  // the shader's sample indices: first_sample .. first_sample + spp − 1
    renderer_.render_frame(c);
    double ms = 0;
    for (const gpu::PassTiming& t : renderer_.last_timings()) ms += t.ms;
    return ms;
  }
  const gpu::Renderer& renderer() const { return renderer_; }

 private:
  static gpu::RendererOptions renderer_options(const Scene& scene, const ReferenceOptions& o) {
    gpu::RendererOptions r;
    r.width = o.width;
    r.height = o.height;
    r.gbuffer = false;
    r.reference = true;
    r.reference_options.background = scene.background;
    r.reference_options.direct_only = o.direct_only;
    r.reference_options.max_bounces = o.max_bounces;
    return r;
  }
  FlatGeometry geometry_;
  FlatInstances flat_;
  GpuCamera camera_;
  ReferenceOptions options_;
  gpu::Renderer renderer_;
};

nlohmann::json cost_json(const RenderCost& c) {
  return {{"fixed_ms", json_figure(c.fixed_ms)}, {"per_spp_ms", json_figure(c.per_spp_ms)}};
}

nlohmann::json optional_figure(const std::optional<double>& v) { return v ? json_figure(*v) : nlohmann::json(nullptr); }

// One peer's row: its render at the budget against the reference, and the
// times it needs to reach the realtime output's two errors. v1 (per-sample
// relMSE) comes from `noise_images`, a render of noise_spp ≥ 16 samples: the
// halves of a render of 1 or 2 samples are too few to estimate it.
struct PeerImages {
  Image mean, half_a, half_b;
};

nlohmann::json peer_row(const RenderCost& cost, std::uint32_t spp, std::uint32_t first_sample, double ms,
                        const PeerImages& images, const PeerImages& noise_images, std::uint32_t noise_spp,
                        const EqualTimeTarget& t, double reference_noise) {
  const ReferenceResult& ref = *t.reference;
  const RealtimePoint& rt = t.realtime;
  const double err = relmse(images.mean, ref.mean);
  const double v1 = estimator_noise(noise_images.half_a, noise_images.half_b, ref.mean) * double(noise_spp);
  const double noise = v1 / double(spp);  // of this render's mean
  const std::optional<double> frame_ms = equal_error_ms(cost, v1, reference_noise, rt.frame_relmse);
  const std::optional<double> temporal_ms = equal_error_ms(cost, v1, reference_noise, rt.temporal_relmse);
  const double realtime_temporal_ms = rt.ms_per_frame * double(rt.window_frames);
  nlohmann::json row = {
      {"spp", spp},
      {"sample_indices", {first_sample, first_sample + spp}},  // [first, end)
      {"ms", json_figure(ms)},
      // One sample costs more than the realtime frame: the row is the peer's
      // fastest render, not one at equal time.
      {"fits_budget", cost.fixed_ms + cost.per_spp_ms <= rt.ms_per_frame},
      {"cost", cost_json(cost)},
      {"relmse", json_figure(err)},
      {"noise_relmse", json_figure(noise)},
      {"relmse_over_expected", json_figure(err / (noise + reference_noise))},
      {"per_sample_relmse", json_figure(v1)},
      {"per_sample_relmse_from_spp", noise_spp},
      {"relmse_over_realtime_frame", json_figure(err / rt.frame_relmse)},
      {"ms_to_realtime_frame_error", optional_figure(frame_ms)},
      {"ms_to_realtime_temporal_error", optional_figure(temporal_ms)},
      {"equal_error_time_ratio_frame", frame_ms && rt.ms_per_frame > 0 ? json_figure(*frame_ms / rt.ms_per_frame)
                                                                        : nlohmann::json(nullptr)},
      {"equal_error_time_ratio_temporal", temporal_ms && realtime_temporal_ms > 0
                                              ? json_figure(*temporal_ms / realtime_temporal_ms)
                                              : nlohmann::json(nullptr)}};
  return row;
}

}  // namespace

std::uint32_t RenderCost::spp_within(double budget_ms) const {
  const double n = per_spp_ms > 0 ? std::floor((budget_ms - fixed_ms) / per_spp_ms) : 1.0;
  return static_cast<std::uint32_t>(std::clamp(std::isfinite(n) ? n : 1.0, 1.0, 65536.0));
}

RenderCost measure_cost(const std::function<double(std::uint32_t)>& render, int repeats) {
  double t1 = 1e300, tn = 1e300;
  for (int r = 0; r < repeats; ++r) {
    t1 = std::min(t1, render(1));
    tn = std::min(tn, render(kCalibrationSpp));
  }
  RenderCost c;
  c.per_spp_ms = (tn - t1) / double(kCalibrationSpp - 1);
  c.fixed_ms = t1 - c.per_spp_ms;
  if (!(c.per_spp_ms > 0) || c.fixed_ms < 0) c = {0.0, tn / double(kCalibrationSpp)};  // timer noise: all per sample
  return c;
}

std::optional<double> equal_error_ms(const RenderCost& cost, double v1, double reference_noise, double error) {
  if (!(error > reference_noise) || !std::isfinite(error) || !(v1 >= 0)) return std::nullopt;
  return cost.fixed_ms + cost.per_spp_ms * v1 / (error - reference_noise);
}

nlohmann::json equal_time_figures(gpu::Device* device, gpu::ShaderCompiler* compiler, const EqualTimeTarget& t) {
  const ReferenceResult& ref = *t.reference;
  const ReferenceOptions& ro = t.reference_options;
  const double reference_noise = estimator_noise(ref.half_a, ref.half_b, ref.mean);
  const double budget = t.realtime.ms_per_frame;
  // Fresh sample indices: the reference used 0 .. spp − 1 (and the GPU path
  // tracer draws from an RNG domain of its own besides).
  const std::uint32_t first_sample = ro.spp;
  nlohmann::json out = {
      {"method",
       "peers at the realtime pipeline's ms/frame (sum of its passes' median GPU times, one chain's: the passes run per chain divided by the chains), on sample indices the "
       "reference did not use; cost = fixed + spp x per-spp from renders at 1 and 16 spp (fastest of 3); the time "
       "to reach an error E: fixed + per_spp x v1 / (E - r), v1 the peer's per-sample relMSE, r the reference's "
       "noise; ratio = that time / the realtime time to the same error (1 frame; the window's frames for the "
       "temporal mean): above 1 the realtime pipeline is faster"},
      {"reference", {{"spp", ro.spp}, {"sample_indices", {0, ro.spp}}, {"noise_relmse", json_figure(reference_noise)},
                     {"direct_only", ro.direct_only}}},
      {"realtime", {{"ms_per_frame", json_figure(budget)},
                    {"frame_relmse", json_figure(t.realtime.frame_relmse)},
                    {"temporal_relmse", json_figure(t.realtime.temporal_relmse)},
                    {"window_frames", t.realtime.window_frames}}}};
  if (device && compiler) {
    GpuPathTracer pt(*device, *compiler, *t.scene, ro);
    pt.render(1, first_sample);  // first use: the pipeline's compilation (lavapipe JITs at first dispatch)
    const RenderCost cost = measure_cost([&](std::uint32_t spp) { return pt.render(spp, first_sample); });
    const std::uint32_t spp = cost.spp_within(budget);
    const double ms = pt.render(spp, first_sample);
    const gpu::Renderer& r = pt.renderer();
    const PeerImages images{r.reference_mean(), r.reference_half(0), r.reference_half(1)};
    const std::uint32_t noise_spp = std::max(spp, kCalibrationSpp);
    if (noise_spp != spp) pt.render(noise_spp, first_sample + spp);  // still indices the reference did not use
    const PeerImages noise{r.reference_mean(), r.reference_half(0), r.reference_half(1)};
    out["gpu_path_tracer"] = peer_row(cost, spp, first_sample, ms, images, noise, noise_spp, t, reference_noise);
    out["gpu_path_tracer"]["device"] = device->info().name;
    out["gpu_path_tracer"]["rng_domain"] = "gpu_reference";
  }
  if (t.embree) {
    ReferenceOptions eq = ro;
    eq.first_sample = first_sample;
    const RenderCost cost = t.embree_cost ? *t.embree_cost : measure_cost([&](std::uint32_t spp) {
      eq.spp = spp;
      return render_reference(*t.scene, eq).seconds * 1000.0;
    });
    eq.spp = cost.spp_within(budget);
    const ReferenceResult r = render_reference(*t.scene, eq);
    const std::uint32_t noise_spp = std::max(eq.spp, kCalibrationSpp);
    ReferenceOptions more = eq;
    more.spp = noise_spp;
    more.first_sample = eq.first_sample + eq.spp;
    const ReferenceResult n = noise_spp != eq.spp ? render_reference(*t.scene, more) : r;
    out["embree"] = peer_row(cost, eq.spp, first_sample, r.seconds * 1000.0, PeerImages{r.mean, r.half_a, r.half_b},
                             PeerImages{n.mean, n.half_a, n.half_b}, noise_spp, t, reference_noise);
    out["embree"]["rng_domain"] = "embree";
  }
  return out;
}

}  // namespace gi
