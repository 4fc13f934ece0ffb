#include "reports/speed_error_report.h"

#include <cmath>

#include <fmt/format.h>

#include "reports/html_page.h"
#include "reports/summary.h"

namespace gi {
namespace {

double number_or_nan(const nlohmann::json& v) { return v.is_number() ? v.get<double>() : std::nan(""); }

const nlohmann::json& object_or_empty(const nlohmann::json& j, const char* key) {
  static const nlohmann::json empty = nlohmann::json::object();
  return j.is_object() && j.contains(key) && j[key].is_object() ? j[key] : empty;
}

// The last frame the reference check compared: {relmse of the realtime
// frame or the accumulated image, realtime?}.
std::pair<double, bool> last_error(const nlohmann::json& summary) {
  for (const nlohmann::json& c : summary.value("checks", nlohmann::json::array())) {
    if (c.value("name", "") != "reference") continue;
    const nlohmann::json frames = object_or_empty(c, "figures").value("frames", nlohmann::json::array());
    if (frames.empty()) continue;
    const nlohmann::json& f = frames.back();
    if (f.contains("per_frame")) return {number_or_nan(object_or_empty(f, "per_frame").value("relmse", nlohmann::json())), true};
    return {number_or_nan(f.value("relmse", nlohmann::json())), false};
  }
  return {std::nan(""), false};
}

std::string cell(const nlohmann::json& v) { return v.is_number() ? html_figure(v) : "&ndash;"; }

}  // namespace

Plot speed_against_error_plot(const std::vector<NamedSummary>& runs) {
  PlotSeries accumulated{"reference mode (accumulated image)", {}, {}, false};
  PlotSeries realtime{"realtime (one frame)", {}, {}, false};
  PlotSeries gpu_pt{"GPU path tracer at a realtime scene's ms/frame", {}, {}, false};
  PlotSeries embree{"Embree at a realtime scene's ms/frame", {}, {}, false};
  for (const NamedSummary& r : runs) {
    const nlohmann::json& s = *r.summary;
    // A realtime run's point at one chain's cost, the peers' budget.
    const std::uint32_t chains = object_or_empty(s, "resolved").value("chains", 0u);
    const double ms = chains > 0 ? one_chain_ms_per_frame(object_or_empty(s, "timings"), chains)
                                 : pipeline_ms_per_frame(object_or_empty(s, "timings"));
    const auto [error, is_realtime] = last_error(s);
    if (std::isfinite(error)) {
      PlotSeries& series = is_realtime ? realtime : accumulated;
      series.points.emplace_back(ms, error);
      series.labels.push_back(r.name);
    }
    const nlohmann::json& eq = object_or_empty(s, "equal_time");
    for (auto [key, series] : {std::pair{"gpu_path_tracer", &gpu_pt}, std::pair{"embree", &embree}}) {
      const nlohmann::json& peer = object_or_empty(eq, key);
      if (peer.empty()) continue;
      series->points.emplace_back(number_or_nan(peer.value("ms", nlohmann::json())),
                                  number_or_nan(peer.value("relmse", nlohmann::json())));
      series->labels.push_back(fmt::format("{} spp", peer.value("spp", 0u)));
    }
  }
  return Plot{"speed against error (realtime: one frame; path tracers at that frame's time)",
              "ms/frame (GPU passes, realtime: one chain's; path tracers: their render)", "relMSE against Embree", true, true,
              {accumulated, realtime, gpu_pt, embree}};
}

std::string speed_against_error_tables(const std::vector<NamedSummary>& runs) {
  std::vector<std::vector<std::string>> equal, signals;
  for (const NamedSummary& r : runs) {
    const nlohmann::json& eq = object_or_empty(*r.summary, "equal_time");
    if (eq.empty()) continue;
    const nlohmann::json& rt = object_or_empty(eq, "realtime");
    const nlohmann::json& pt = object_or_empty(eq, "gpu_path_tracer");
    const nlohmann::json& em = object_or_empty(eq, "embree");
    auto peer = [](const nlohmann::json& p) {
      return p.empty() ? std::string("&ndash;")
                       : fmt::format("{} ({} spp, {} ms{})", cell(p.value("relmse", nlohmann::json())),
                                     p.value("spp", 0u), cell(p.value("ms", nlohmann::json())),
                                     p.value("fits_budget", true) ? "" : "; one sample exceeds the realtime frame");
    };
    equal.push_back({html_escape(r.name), cell(rt.value("ms_per_frame", nlohmann::json())),
                     cell(rt.value("frame_relmse", nlohmann::json())), peer(pt), peer(em),
                     cell(pt.value("equal_error_time_ratio_frame", nlohmann::json())),
                     cell(em.value("equal_error_time_ratio_frame", nlohmann::json())),
                     cell(rt.value("temporal_relmse", nlohmann::json())),
                     cell(pt.value("equal_error_time_ratio_temporal", nlohmann::json())),
                     cell(object_or_empty(eq, "reference").value("noise_relmse", nlohmann::json()))});
    const nlohmann::json& sig = object_or_empty(eq, "signals");
    for (const char* name : {"di", "gi", "specular", "indirect"}) {
      const nlohmann::json& f = object_or_empty(sig, name);
      if (f.empty()) continue;
      const nlohmann::json& bias = object_or_empty(f, "bias");
      signals.push_back({html_escape(r.name), name, cell(f.value("noise_chain", nlohmann::json())),
                         cell(f.value("noise_temporal", nlohmann::json())),
                         cell(bias.value("relmse", nlohmann::json())), cell(bias.value("combined_noise", nlohmann::json())),
                         cell(bias.value("energy_ratio", nlohmann::json())), cell(f.value("ms", nlohmann::json()))});
    }
  }
  if (equal.empty()) return "<p>no realtime scenario measured the path tracers at equal time</p>\n";
  std::string html =
      "<h3>At equal time, same device</h3>\n<p class=\"small\">Per-frame relMSE against the scene's Embree "
      "reference (which carries its own noise, last column). Peers: the GPU path tracer on the realtime run's device "
      "and Embree on the CPU, each at the spp its measured cost fits into the realtime ms/frame, on sample indices "
      "the reference did not use. Equal-error time ratio: the time the path tracer needs for the realtime error, "
      "over the realtime time (one frame; the window's frames for the temporal mean): above 1 the realtime "
      "pipeline is faster.</p>\n";
  html += html_table({"scenario", "realtime ms/frame", "realtime relMSE (frame)", "GPU path tracer relMSE",
                      "Embree relMSE", "equal-error time ratio, GPU path tracer (frame)",
                      "equal-error time ratio, Embree (frame)", "realtime relMSE (temporal mean)",
                      "equal-error time ratio, GPU path tracer (temporal mean)", "reference noise"},
                     equal);
  if (!signals.empty())
    html += "<h3>Per signal</h3>\n<p class=\"small\">Noise: relMSE of one chain's signal per frame (chain: the "
            "two chains' difference; temporal: the flicker over the window), on the whole output's scale so the "
            "signals add up. Bias: the signal's two-chain temporal mean against Embree's same quantity (DI: "
            "direct lighting; indirect: full minus direct), on the signal's own scale.</p>\n" +
            html_table({"scenario", "signal", "noise (chain)", "noise (temporal)", "relMSE vs Embree",
                        "combined noise", "energy ratio", "ms"},
                       signals);
  return html;
}

}  // namespace gi
