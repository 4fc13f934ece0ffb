// `giharness reference`: the Embree reference image of a scenario's scene
// state at one frame, with its noise estimate and ray rate.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/metrics.h"
#include "core/png_preview.h"
#include "core/reference/reference_cache.h"
#include "core/profile.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "checks/reference_check.h"
#include "app/commands.h"
#include "core/scene_events.h"
#include "gpu/realtime_settings.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {

int run_reference_command(const ReferenceCommandOptions& o) {
  const Scenario scenario = load_scenario(o.scenario);
  Scene initial = build_scene(scenario);
  apply_material_model(initial, resolve_profile(scenario));  // as a run of the scenario shades it
  const std::uint32_t frame = o.frame.value_or(scenario.frames - 1);
  if (frame >= scenario.frames)
    throw InputError("--frame", "", fmt::format("expected a frame below the scenario's {} frames", scenario.frames));
  const Scene scene = scene_at_frame(initial, scenario, frame);

  ReferenceOptions options;
  options.width = scenario.resolution[0];
  options.height = scenario.resolution[1];
  options.seed = scenario.seed;
  options.threads = o.threads;
  options.spp = o.spp.value_or(scenario_reference_spp(scenario, 1024));
  if (options.spp < 2) throw InputError("--spp", "", "expected at least 2 samples (two halves estimate the noise)");

  bool hit = false;
  const ReferenceResult r = cached_reference(scene, options, cache_root() / "reference", &hit);
  std::filesystem::create_directories(o.out_dir);
  write_exr(o.out_dir / "reference.exr", {{"", &r.mean}, {"half_a", &r.half_a}, {"half_b", &r.half_b}});
  write_png_preview(o.out_dir / "reference.png", r.mean);

  const double noise = estimator_noise(r.half_a, r.half_b, r.mean);
  nlohmann::json s;
  s["schema_version"] = 1;
  s["scenario"] = {{"name", scenario.name}, {"file", scenario.file.string()}};
  s["frame"] = frame;
  s["resolution"] = {options.width, options.height};
  s["spp"] = options.spp;
  s["seed"] = options.seed;
  s["cached"] = hit;
  s["seconds"] = json_figure(r.seconds);
  s["seconds_per_1000_spp"] = json_figure(r.seconds * 1000.0 / options.spp);
  s["rays"] = r.rays;
  s["mrays_per_second"] = json_figure(r.seconds > 0 ? static_cast<double>(r.rays) / r.seconds * 1e-6 : 0.0);
  s["noise_relmse"] = json_figure(noise);
  s["mean_luminance"] = json_figure(mean_luminance(r.mean));
  s["nonfinite_samples"] = r.nonfinite_samples;
  s["integrator_version"] = reference_integrator_version();
  s["build"] = build_info();
  write_json_file(o.out_dir / "summary.json", s);
  spdlog::info("{}: reference frame {} at {}x{}, {} spp: {:.2f} s{} ({:.1f} Mrays/s), noise relMSE {:.3g}",
               scenario.name, frame, options.width, options.height, options.spp, r.seconds,
               hit ? " (cached)" : "", s["mrays_per_second"].get<double>(), noise);
  return r.nonfinite_samples == 0 ? 0 : 1;
}

}  // namespace gi
