// `giharness sweep SCENARIO --vary key=v1,v2,… [--vary …] --out DIR`
// (docs/design.md §10, §12): runs every point of the cartesian product, measures each
// point's GPU ms/frame (sum of its passes' median timestamps) and the relMSE of its
// last frame against a converged Embree reference, and puts the path tracers
// given the same time per frame in the same table and plot
// (replay/equal_time.h): the GPU path tracer on the same device (realtime
// points) and Embree on the CPU, each at the spp that fits the point's
// ms/frame by its measured cost, on fresh sample indices, against the same
// reference, with the time each needs to reach the point's error.
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
#include "gpu/realtime_settings.h"
#include "core/reference/embree_reference.h"
#include "core/reference/reference_cache.h"
#include "core/scene_builder.h"
#include "replay/capture.h"
#include "checks/reference_check.h"
#include "app/commands.h"
#include "core/scene_events.h"
#include "app/sweep_plan.h"
#include "app/rc_sweep.h"
#include "replay/equal_time.h"
#include "replay/signal_figures.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "core/cache_root.h"
#include "reports/gnuplot.h"
#include "reports/html_page.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

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

std::string row_figure(const nlohmann::json& row, const char* key) {
  return row.contains(key) && row[key].is_number() ? table_number(row[key].get<double>()) : "&ndash;";
}

// "di 1.2, gi 3.4, …" from a GPU row's ms per signal.
std::string signal_ms_cell(const nlohmann::json& row) {
  std::string cell;
  const nlohmann::json ms = row.value("signal_ms", nlohmann::json::object());  // items() of a temporary would dangle
  for (const auto& [signal, v] : ms.items())
    cell += (cell.empty() ? "" : ", ") + signal + " " + table_number(v.is_number() ? v.get<double>() : std::nan(""));
  return cell.empty() ? "&ndash;" : cell;
}

void write_sweep_report(const std::filesystem::path& out_dir, const nlohmann::json& sweep) {
  PlotSeries gpu{"realtime pipeline", {}, {}, false}, gpu_pt{"GPU path tracer at equal time", {}, {}, false},
      embree{"Embree at equal time", {}, {}, false};
  std::vector<std::vector<std::string>> rows;
  for (const nlohmann::json& r : sweep["rows"]) {
    const double ms = r["ms_per_frame"].is_number() ? r["ms_per_frame"].get<double>() : std::nan("");
    const double err = r["relmse"].is_number() ? r["relmse"].get<double>() : std::nan("");
    const std::string kind = r["kind"];
    const bool is_gpu = kind == "gpu";
    PlotSeries& series = is_gpu ? gpu : kind == "gpu_path_tracer_equal_time" ? gpu_pt : embree;
    series.points.emplace_back(ms, err);
    series.labels.push_back(is_gpu ? r["label"].get<std::string>() : fmt::format("{} spp", r["spp"].get<unsigned>()));
    const std::string renderer = is_gpu ? "GPU" : kind == "gpu_path_tracer_equal_time" ? "GPU path tracer (equal time)"
                                                                                        : "Embree (equal time)";
    rows.push_back({renderer, html_escape(r["label"].get<std::string>()), table_number(ms), table_number(err),
                    r.contains("spp") ? r["spp"].dump() : "&ndash;", row_figure(r, "embree_over_gpu_relmse"),
                    row_figure(r, "equal_error_time_ratio_frame"), is_gpu ? signal_ms_cell(r) : "&ndash;",
                    noise_cell(r),
                    "<a href=\"" + html_escape(r.value("summary", "")) + "\">" + html_escape(r.value("summary", "")) + "</a>"});
  }
  Plot plot{"error against time per frame", "ms/frame", "relMSE against the converged reference", true, true,
            {gpu, gpu_pt, embree}};
  const std::vector<PlotResult> drawn = render_plots({plot}, out_dir / "plots");
  std::string body = "<h1>giharness sweep: " + html_escape(sweep["scenario"].get<std::string>()) + "</h1>\n";
  body += "<p>" + html_escape(sweep["method"].get<std::string>()) + "</p>\n";
  std::set<std::string> references;  // one line per distinct reference, not per point
  for (nlohmann::json r : sweep["reference"]) {
    r.erase("point");
    references.insert(r.dump());
  }
  for (const std::string& r : references) body += "<p class=\"small\">converged reference: " + html_escape(r) + "</p>\n";
  body += html_table({"renderer", "point", "ms/frame", "relMSE", "spp", "Embree relMSE / GPU relMSE",
                      "equal-error time ratio (peer time to the point's error / the point's ms)", "ms per signal",
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
  if (base.pipeline == Pipeline::RadianceCascades) return run_rc_sweep(o, base, points, scenarios);
  const std::uint32_t reference_spp = o.reference_spp.value_or(scenario_reference_spp(base, 1024));

  nlohmann::json sweep = {{"schema_version", 1},
                          {"scenario", base.file.string()},
                          {"vary", o.vary},
                          {"build", build_info()},
                          {"method",
                           "GPU: ms/frame = sum of the pipeline passes' median timestamps (observation passes left "
                           "out; for a realtime point one chain's: passes run per chain divided by the chains); relMSE of the last frame against a converged Embree reference. Path tracers at "
                           "equal time (the GPU one on the same device for realtime points, and Embree): the "
                           "samples per pixel that fit the GPU's ms/frame at the tracer's measured cost (a "
                           "per-render and a per-sample part), on sample indices the reference did not use, "
                           "against the same reference; the equal-error time ratio is the time the tracer needs "
                           "for the point's relMSE over the point's ms/frame (replay/equal_time.h)."},
                          {"rows", nlohmann::json::array()}};
  nlohmann::json references = nlohmann::json::array();
  std::map<std::uint64_t, RenderCost> embree_costs;
  std::optional<gpu::Device> peer_device;  // the GPU path tracer's: the device the points ran on
  std::optional<gpu::ShaderCompiler> peer_compiler;
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
    // A realtime point's ms/frame is one chain's (with --noise the run renders two).
    const std::uint32_t chains = run.summary["resolved"].value("chains", 1u);
    const double ms = chains > 0 ? one_chain_ms_per_frame(timings, chains) : pipeline_ms_per_frame(timings);
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

    // The peers at this point's ms/frame: the GPU path tracer on the sweep's
    // device (realtime points: a reference-mode point is that tracer itself)
    // and Embree.
    EqualTimeTarget target;
    target.scene = &scene;
    target.reference_options = ref_options;
    target.reference = &reference;
    target.realtime = {ms, gpu_relmse, std::nan(""), 0};
    // One Embree calibration per scene state and resolution (keyed with spp
    // 0): every point of one scene shares it, as its cost does not depend on
    // the pipeline's settings.
    ReferenceOptions key_options = ref_options;
    key_options.spp = 0;
    const std::uint64_t key = reference_cache_key(scene, key_options);
    if (const auto c = embree_costs.find(key); c != embree_costs.end()) target.embree_cost = c->second;
    const bool realtime = s.mode == RenderMode::Realtime;
    if (realtime && !peer_device) {
      peer_device.emplace(o.device, gpu::BackendRequest::automatic);
      peer_compiler.emplace(cache_root());
    }
    const nlohmann::json peers = equal_time_figures(realtime ? &*peer_device : nullptr,
                                                    realtime ? &*peer_compiler : nullptr, target);
    const nlohmann::json& embree = peers["embree"];
    embree_costs[key] = {embree["cost"]["fixed_ms"].get<double>(), embree["cost"]["per_spp_ms"].get<double>()};
    const double embree_relmse = embree["relmse"].get<double>();
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
                             {"signal_ms", signal_ms(timings, chains)},
                             {"chains", chains},
                             {"ms_per_frame_all_chains", json_figure(pipeline_ms_per_frame(timings))},
                             {"summary", folder + "/summary.json"},
                             {"timings", timings}});
    for (const char* peer : {"gpu_path_tracer", "embree"}) {
      if (!peers.contains(peer)) continue;
      nlohmann::json row = peers[peer];
      row["kind"] = std::string(peer) + "_equal_time";
      row["point"] = i;
      row["label"] = "equal time to " + p.label();
      row["ms_per_frame"] = row["ms"];
      row["budget_ms"] = json_figure(ms);
      sweep["rows"].push_back(row);
    }
    const nlohmann::json& gpu_pt = peers.value("gpu_path_tracer", nlohmann::json::object());
    if (!gpu_pt.empty())
      spdlog::info("[{}/{}] {}: GPU path tracer {} spp in {:.3f} ms: relMSE {:.4g}; equal-error time ratio {}", i + 1,
                   points.size(), p.label(), gpu_pt["spp"].get<unsigned>(), gpu_pt["ms"].get<double>(),
                   gpu_pt["relmse"].get<double>(), gpu_pt["equal_error_time_ratio_frame"].dump());
    spdlog::info("[{}/{}] {}: {:.3f} ms/frame, relMSE {:.4g}; Embree {} spp in {:.3f} ms: relMSE {:.4g} ({:.3g}x the GPU's)",
                 i + 1, points.size(), p.label(), ms, gpu_relmse, embree["spp"].get<unsigned>(),
                 embree["ms"].get<double>(), embree_relmse, embree_relmse / gpu_relmse);
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
