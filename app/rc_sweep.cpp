// The radiance-cascades sweep: every point runs the scenario (its frames; the
// canvas at the last one is judged), and gives
//   - ms/frame: the median over frames of the RC passes' GPU time summed;
//   - its error against a converged 2D path tracer (core/rc/rc_reference.h,
//     --reference-spp rays per pixel, default 16384) over the pixels outside
//     every shape: relative L1, Σ|Y − Y_ref| / ΣY_ref, and relMSE,
//     Σ(Y − Y_ref)² / ΣY_ref², and the energy ratio;
//   - the 2D path tracer at equal time: the rays per pixel its measured cost
//     on this machine fits in the point's ms/frame (the tracer runs on the
//     CPU cores lavapipe's GPU runs on), on a seed the converged one did not
//     use, and its error against the same reference;
//   - the path tracer's own curve (2 … 2048 rays per pixel, measured once per
//     canvas) and from it the time it needs to reach the point's error.
// Writes <out>/sweep.json, <out>/report.html with the table and the plot.
#include "app/rc_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/exr_io.h"
#include "core/rc/rc_reference.h"
#include "reports/change.h"
#include "reports/gnuplot.h"
#include "reports/html_page.h"
#include "reports/summary.h"
#include "replay/run_scenario.h"

namespace gi {
namespace {

nlohmann::json errors_json(const RcComparison& c) {
  return {{"relative_l1", c.relative_l1()}, {"relmse", c.relmse()}, {"energy_ratio", c.energy_ratio()}};
}

std::string cell(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : "&ndash;"; }

}  // namespace

int run_rc_sweep(const SweepOptions& o, const Scenario& base, const std::vector<SweepPoint>& points,
                 const std::vector<Scenario>& scenarios) {
  const std::uint32_t reference_rays = o.reference_spp.value_or(16384);
  nlohmann::json sweep = {
      {"schema_version", 1},
      {"scenario", base.file.string()},
      {"pipeline", "radiance_cascades"},
      {"vary", o.vary},
      {"build", build_info()},
      {"method",
       fmt::format("Radiance cascades: ms/frame = median over the run's frames of the RC passes' GPU timestamps "
                   "summed; error of the last frame against the 2D path tracer at {} rays per pixel over the pixels "
                   "outside every shape: relative L1 = sum |Y - Y_ref| / sum Y_ref, relMSE = sum (Y - Y_ref)^2 / sum "
                   "Y_ref^2. 2D path tracer at equal time: the rays per pixel that its measured cost on this "
                   "machine's CPU cores fits in the point's ms/frame, on a seed the reference did not use.",
                   reference_rays)},
      {"rows", nlohmann::json::array()}};
  PlotSeries rc_series{"radiance cascades", {}, {}, false}, pt_series{"2D path tracer at equal time", {}, {}, false};
  std::vector<std::vector<std::string>> table;
  std::map<std::uint64_t, RcReference> converged;
  std::map<std::uint64_t, PlotSeries> ladders;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SweepPoint& p = points[i];
    const Scenario& s = scenarios[i];
    RunOptions ro;
    ro.out_dir = o.out_dir / p.slug();
    ro.device = o.device;
    ro.quiet = true;
    const RunResult run = run_scenario(s, ro);
    const Image image = read_exr(ro.out_dir / kFinalImageFile).at("");
    const double ms = run.summary["timings"]["frame"]["pipeline_pass_sum_median_ms"].get<double>();
    const Canvas canvas = canvas_at_frame(*s.canvas, s, s.frames - 1);
    auto [it, fresh] = converged.try_emplace(canvas.hash());
    if (fresh) {
      it->second = rc_reference(canvas, {.rays = reference_rays, .seed = 0x5EEDu});
      // The path tracer's own curve on this canvas: 2, 4, … 2048 rays per pixel.
      PlotSeries& curve = ladders[canvas.hash()];
      curve.title = "2D path tracer, 2 to 2048 rays per pixel";
      for (std::uint32_t r = 2; r <= 2048; r *= 2) {
        const RcReference run = rc_reference(canvas, {.rays = r, .seed = 13});
        curve.points.emplace_back(run.seconds * 1000.0, rc_compare(run.mean, it->second).relative_l1());
        curve.labels.push_back(std::to_string(r));
      }
    }
    const RcReference& ref = it->second;
    const RcComparison e = rc_compare(image, ref);
    // The path tracer's cost, a per-render and a per-ray part, from two short runs.
    const double t16 = rc_reference(canvas, {.rays = 16, .seed = 7}).seconds * 1000.0;
    const double t64 = rc_reference(canvas, {.rays = 64, .seed = 7}).seconds * 1000.0;
    const double per_ray = std::max((t64 - t16) / 48.0, 1e-6), fixed = std::max(t16 - 16.0 * per_ray, 0.0);
    const auto rays = std::uint32_t(std::clamp(std::floor((ms - fixed) / per_ray / 2.0) * 2.0, 2.0, 1e6));
    const RcReference equal = rc_reference(canvas, {.rays = rays, .seed = 11});
    const RcComparison pe = rc_compare(equal.mean, ref);
    const nlohmann::json settings = run.summary["resolved"]["radiance_cascades"];
    // The time the path tracer needs for the point's error, log-log between
    // the two rungs of its curve around it (none past its last rung).
    double equal_error_ms = std::nan("");
    const auto& curve = ladders[canvas.hash()].points;
    for (std::size_t k = 0; k + 1 < curve.size(); ++k) {
      const auto [t0, e0] = curve[k];
      const auto [t1, e1] = curve[k + 1];
      if (e0 >= e.relative_l1() && e1 <= e.relative_l1() && e0 > e1) {
        const double u = std::log(e0 / e.relative_l1()) / std::log(e0 / e1);
        equal_error_ms = std::exp(std::log(t0) + u * (std::log(t1) - std::log(t0)));
        break;
      }
    }
    sweep["rows"].push_back({{"kind", "radiance_cascades"}, {"label", p.label()}, {"ms_per_frame", ms},
                             {"errors", errors_json(e)}, {"settings", settings}, {"checks_verdict", run.summary["verdict"]},
                             {"path_tracer_ms_to_equal_error", std::isfinite(equal_error_ms) ? nlohmann::json(equal_error_ms) : nlohmann::json(nullptr)},
                             {"summary", (std::filesystem::path(p.slug()) / "summary.json").string()}});
    sweep["rows"].push_back({{"kind", "path_tracer_2d_equal_time"}, {"label", p.label()}, {"rays", rays},
                             {"ms_per_frame", equal.seconds * 1000.0}, {"errors", errors_json(pe)}});
    rc_series.points.emplace_back(ms, e.relative_l1());
    rc_series.labels.push_back(p.label());
    pt_series.points.emplace_back(equal.seconds * 1000.0, pe.relative_l1());
    pt_series.labels.push_back(fmt::format("{} rays", rays));
    table.push_back({html_escape(p.label()), cell(ms), cell(e.relative_l1()), cell(e.relmse()), cell(e.energy_ratio()),
                     std::to_string(settings["cascades"].get<unsigned>()), std::to_string(rays),
                     cell(equal.seconds * 1000.0), cell(pe.relative_l1()), cell(pe.relmse()), cell(equal_error_ms)});
    spdlog::info("sweep {}: {:.3f} ms/frame, relative L1 {:.4f} (path tracer at equal time: {} rays, {:.4f})", p.label(),
                 ms, e.relative_l1(), rays, pe.relative_l1());
  }
  std::filesystem::create_directories(o.out_dir);
  std::vector<PlotSeries> series = {rc_series, pt_series};
  for (auto& [_, curve] : ladders) series.push_back(curve);
  sweep["path_tracer_curves"] = nlohmann::json::array();
  for (const auto& [_, curve] : ladders) {
    nlohmann::json c = nlohmann::json::array();
    for (std::size_t k = 0; k < curve.points.size(); ++k)
      c.push_back({{"rays", std::stoi(curve.labels[k])}, {"ms", curve.points[k].first}, {"relative_l1", curve.points[k].second}});
    sweep["path_tracer_curves"].push_back(c);
  }
  write_json_file(o.out_dir / "sweep.json", sweep);
  const Plot plot{"radiance cascades: error against time per frame", "ms/frame", "relative L1 against the 2D path tracer",
                  true, true, series};
  const std::vector<PlotResult> drawn = render_plots({plot}, o.out_dir / "plots");
  std::string body = "<h1>giharness sweep (radiance cascades): " + html_escape(base.file.string()) + "</h1>\n";
  body += "<p>" + html_escape(sweep["method"].get<std::string>()) + "</p>\n";
  body += html_table({"point", "ms/frame", "relative L1", "relMSE", "energy ratio", "cascades",
                      "path tracer rays (equal time)", "path tracer ms", "path tracer relative L1",
                      "path tracer relMSE", "path tracer ms to the point's relative L1"},
                     table);
  body += html_plot(drawn[0], "error against time per frame");
  write_text_file(o.out_dir / "report.html", html_page("giharness sweep", body));
  spdlog::info("sweep: {} points; table {}; report {}", points.size(), (o.out_dir / "sweep.json").string(),
               (o.out_dir / "report.html").string());
  return 0;
}

}  // namespace gi
