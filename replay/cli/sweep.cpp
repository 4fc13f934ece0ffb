// `giharness sweep SCENARIO --vary key=v1,v2,… [--vary …] --out DIR`
// (DESIGN §10, §12): runs every point of the cartesian product, measures each
// point's GPU ms/frame (sum of its passes' median timestamps) and the relMSE of its
// last frame against a converged Embree reference, and puts the Embree path
// tracer given the same wall time per frame in the same table and plot:
// Embree's time per sample is measured on this machine (two renders, a fixed
// part and a per-sample part), the spp that fits the point's ms/frame is
// rendered on fresh sample indices and compared to the same reference.
// Writes <out>/sweep.json and <out>/report.html; exit 0 unless a point
// cannot run (2 bad input, 3 device).
#include <cmath>
#include <fstream>
#include <map>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/metrics.h"
#include "core/profile.h"
#include "replay/realtime_settings.h"
#include "core/reference/embree_reference.h"
#include "core/reference/reference_cache.h"
#include "core/scene_builder.h"
#include "replay/capture.h"
#include "replay/checks/reference_check.h"
#include "replay/cli/commands.h"
#include "replay/events.h"
#include "replay/cli/sweep_plan.h"
#include "reports/gnuplot.h"
#include "reports/html_page.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

constexpr std::uint32_t kCalibrationSpp = 16;
constexpr int kCalibrationRepeats = 3;

struct EmbreeCost {
  double fixed_s = 0, per_spp_s = 0;  // seconds = fixed + spp × per_spp
};

// Renders at 1 and kCalibrationSpp spp separate the per-render cost (flatten,
// BVH build) from the per-sample cost; the fastest of a few repeats, because
// on a shared machine a render is only ever slowed down, never sped up.
EmbreeCost calibrate_embree(const Scene& scene, ReferenceOptions options) {
  double t1 = 1e30, tn = 1e30;
  for (int r = 0; r < kCalibrationRepeats; ++r) {
    options.spp = 1;
    t1 = std::min(t1, render_reference(scene, options).seconds);
    options.spp = kCalibrationSpp;
    tn = std::min(tn, render_reference(scene, options).seconds);
  }
  EmbreeCost c;
  c.per_spp_s = (tn - t1) / double(kCalibrationSpp - 1);
  c.fixed_s = t1 - c.per_spp_s;
  if (c.per_spp_s <= 0 || c.fixed_s < 0) c = {0.0, tn / double(kCalibrationSpp)};  // timer noise: all per sample
  return c;
}

std::string table_number(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : "&ndash;"; }

// "chain: di 0.0027, gi 0.109, …; temporal: …" from a GPU row's noise
// (summary.json "noise").
std::string noise_cell(const nlohmann::json& row) {
  if (!row.contains("noise") || !row["noise"].is_object()) return "&ndash;";
  std::string cell;
  for (const char* kind : {"chain", "temporal"}) {
    const nlohmann::json& k = row["noise"].value(kind, nlohmann::json(nullptr));
    if (!k.is_object() || !k.contains("signals") || k["signals"].empty()) continue;
    cell += std::string(cell.empty() ? "" : "; ") + kind + ":";
    for (const auto& [signal, value] : k["signals"].items())
      cell += " " + signal + " " + table_number(value.is_number() ? value.get<double>() : std::nan(""));
  }
  return cell.empty() ? "&ndash;" : cell;
}

void write_sweep_report(const std::filesystem::path& out_dir, const nlohmann::json& sweep) {
  PlotSeries gpu{"GPU pipeline", {}, {}, false}, embree{"Embree at equal time", {}, {}, false};
  std::vector<std::vector<std::string>> rows;
  for (const nlohmann::json& r : sweep["rows"]) {
    const double ms = r["ms_per_frame"].is_number() ? r["ms_per_frame"].get<double>() : std::nan("");
    const double err = r["relmse"].is_number() ? r["relmse"].get<double>() : std::nan("");
    const bool is_gpu = r["kind"] == "gpu";
    (is_gpu ? gpu : embree).points.emplace_back(ms, err);
    (is_gpu ? gpu : embree).labels.push_back(is_gpu ? r["label"].get<std::string>() : fmt::format("{} spp", r["spp"].get<unsigned>()));
    rows.push_back({is_gpu ? "GPU" : "Embree (equal time)", html_escape(r["label"].get<std::string>()),
                    table_number(ms), table_number(err),
                    r.contains("spp") ? r["spp"].dump() : "&ndash;",
                    r.contains("embree_over_gpu_relmse") ? table_number(r["embree_over_gpu_relmse"].is_number() ? r["embree_over_gpu_relmse"].get<double>() : std::nan("")) : "&ndash;",
                    noise_cell(r),
                    "<a href=\"" + html_escape(r.value("summary", "")) + "\">" + html_escape(r.value("summary", "")) + "</a>"});
  }
  Plot plot{"error against time per frame", "ms/frame", "relMSE against the converged reference", true, true,
            {gpu, embree}};
  const std::vector<PlotResult> drawn = render_plots({plot}, out_dir / "plots");
  std::string body = "<h1>giharness sweep: " + html_escape(sweep["scenario"].get<std::string>()) + "</h1>\n";
  body += "<p>" + html_escape(sweep["method"].get<std::string>()) + "</p>\n";
  std::set<std::string> references;  // one line per distinct reference, not per point
  for (nlohmann::json r : sweep["reference"]) {
    r.erase("point");
    references.insert(r.dump());
  }
  for (const std::string& r : references) body += "<p class=\"small\">converged reference: " + html_escape(r) + "</p>\n";
  body += html_table({"renderer", "point", "ms/frame", "relMSE", "Embree spp", "Embree relMSE / GPU relMSE",
                      "per-frame noise (sweep --noise)", "summary"},
                     rows);
  body += html_plot(drawn[0], "error against time per frame");
  write_text_file(out_dir / "report.html", html_page("giharness sweep", body));
}

}  // namespace

int run_sweep(const SweepOptions& o) {
  const Scenario base = load_scenario(o.scenario);
  std::vector<SweepAxis> axes;
  for (const std::string& item : o.vary) axes.push_back(parse_sweep_axis(item));
  nlohmann::json doc = base.raw;
  // The sweep measures error itself against one converged reference; the
  // scenario's own reference check would render Embree again per point.
  doc["checks"] = without_reference_checks(doc.value("checks", nlohmann::json::array()));
  doc.erase("capture");
  if (o.noise) doc["noise"] = true;
  const std::vector<SweepPoint> points = sweep_points(doc, axes);
  // Validate every point before running any.
  std::vector<Scenario> scenarios;
  for (const SweepPoint& p : points) {
    try {
      scenarios.push_back(parse_scenario(p.document, base.file));
      if (!scenarios.back().overrides.empty()) resolve_profile(scenarios.back());
    } catch (const InputError& e) {
      throw InputError("--vary", p.label(), std::string("a valid scenario: ") + e.what());
    }
  }
  const std::uint32_t reference_spp = o.reference_spp.value_or(scenario_reference_spp(base, 1024));

  nlohmann::json sweep = {{"schema_version", 1},
                          {"scenario", base.file.string()},
                          {"vary", o.vary},
                          {"build", build_info()},
                          {"method",
                           "GPU: ms/frame = sum of the passes' median timestamps; relMSE of the last frame against a "
                           "converged Embree reference. Embree at equal time: the samples per pixel that fit the "
                           "GPU's ms/frame at Embree's measured time per sample (plus its per-render cost), on "
                           "sample indices the reference did not use, against the same reference."},
                          {"rows", nlohmann::json::array()}};
  nlohmann::json references = nlohmann::json::array();
  std::map<std::uint64_t, EmbreeCost> calibrations;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SweepPoint& p = points[i];
    const Scenario& s = scenarios[i];
    const std::uint32_t last = s.frames - 1;
    const std::string folder = fmt::format("points/{:03}_{}", i, p.slug());
    RunOptions ro;
    ro.device = o.device;
    ro.out_dir = o.out_dir / folder;
    ro.capture = {last};
    ro.quiet = true;
    const RunResult run = run_scenario(s, ro);
    const nlohmann::json& timings = run.summary["timings"];
    // Sum of the passes' medians: lavapipe compiles a pipeline at its first
    // dispatch, and that one frame would dominate a mean of a short run.
    double ms = 0;
    for (const auto& [pass, stats] : timings["passes"].items())
      ms += stats["median_ms"].is_number() ? stats["median_ms"].get<double>() : std::nan("");
    const Image gpu_image = read_exr(ro.out_dir / capture_images_file(last)).at("");

    Scene initial = build_scene(s);
    apply_material_model(initial, resolve_profile(s));  // the realtime run's material model
    const Scene scene = scene_at_frame(initial, s, last);
    ReferenceOptions ref_options;
    ref_options.width = s.resolution[0];
    ref_options.height = s.resolution[1];
    ref_options.spp = reference_spp;
    ref_options.seed = s.seed;
    // The realtime mode's output is DI alone unless the scenario runs GI
    // ("gi": true: DI + GI + specular); its reference and its Embree peer
    // integrate the same, as the realtime reference check does.
    ref_options.direct_only = s.mode == RenderMode::Realtime && !s.gi;
    bool hit = false;
    const ReferenceResult reference = cached_reference(scene, ref_options, cache_root() / "reference", &hit);
    const double reference_noise = estimator_noise(reference.half_a, reference.half_b, reference.mean);
    references.push_back({{"point", i}, {"spp", reference_spp}, {"direct_only", ref_options.direct_only},
                          {"noise_relmse", json_figure(reference_noise)},
                          {"cached", hit}, {"seconds", json_figure(reference.seconds)}});
    const double gpu_relmse = relmse(gpu_image, reference.mean);

    ReferenceOptions eq = ref_options;
    eq.first_sample = reference_spp;  // samples the reference did not use
    // One calibration per scene state and resolution (keyed with spp 0, so
    // every point of one scene shares it).
    ReferenceOptions key_options = eq;
    key_options.spp = 0;
    const std::uint64_t key = reference_cache_key(scene, key_options);
    if (!calibrations.count(key)) calibrations[key] = calibrate_embree(scene, eq);
    const EmbreeCost cost = calibrations.at(key);
    const double budget_s = ms / 1000.0;
    eq.spp = static_cast<std::uint32_t>(std::clamp(std::floor((budget_s - cost.fixed_s) / cost.per_spp_s), 1.0, 65536.0));
    const ReferenceResult embree = render_reference(scene, eq);
    const double embree_relmse = relmse(embree.mean, reference.mean);

    sweep["rows"].push_back({{"kind", "gpu"},
                             {"point", i},
                             {"label", p.label()},
                             {"settings", p.settings},
                             {"ms_per_frame", json_figure(ms)},
                             {"relmse", json_figure(gpu_relmse)},
                             {"embree_over_gpu_relmse", json_figure(embree_relmse / gpu_relmse)},
                             {"frames", s.frames},
                             {"checks_exit_code", run.exit_code},
                             {"noise", run.summary.value("noise", nlohmann::json(nullptr))},
                             {"summary", folder + "/summary.json"},
                             {"timings", timings}});
    sweep["rows"].push_back({{"kind", "embree_equal_time"},
                             {"point", i},
                             {"label", "equal time to " + p.label()},
                             {"spp", eq.spp},
                             {"ms_per_frame", json_figure(embree.seconds * 1000.0)},
                             {"budget_ms", json_figure(ms)},
                             {"calibration", {{"fixed_ms", json_figure(cost.fixed_s * 1000.0)},
                                              {"per_spp_ms", json_figure(cost.per_spp_s * 1000.0)}}},
                             {"relmse", json_figure(embree_relmse)}});
    spdlog::info("[{}/{}] {}: {:.3f} ms/frame, relMSE {:.4g}; Embree {} spp in {:.3f} ms: relMSE {:.4g} ({:.3g}x the GPU's)",
                 i + 1, points.size(), p.label(), ms, gpu_relmse, eq.spp, embree.seconds * 1000.0, embree_relmse,
                 embree_relmse / gpu_relmse);
    if (run.summary.contains("noise") && run.summary["noise"].is_object())
      spdlog::info("    per-frame noise: {}", noise_cell({{"noise", run.summary["noise"]}}));
    sweep["reference"] = references;
    write_json_file(o.out_dir / "sweep.json", sweep);
  }
  write_sweep_report(o.out_dir, sweep);
  spdlog::info("sweep: {} points; table {}; report {}", points.size(), (o.out_dir / "sweep.json").string(),
               (o.out_dir / "report.html").string());
  return 0;
}

}  // namespace gi
