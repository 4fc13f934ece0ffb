#include "reports/nightly_report.h"
#include "reports/speed_error_report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/exr_io.h"
#include "core/png_preview.h"
#include "reports/gnuplot.h"
#include "reports/html_page.h"
#include "reports/timing_report.h"

namespace gi {
namespace {

std::string anchor(const std::string& name) {
  std::string out = "s-";
  for (char ch : name) out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '-';
  return out;
}

double number_or_nan(const nlohmann::json& v) { return v.is_number() ? v.get<double>() : std::nan(""); }

// One plot per numeric per-frame key, one plot per nested object (pass_ms:
// a line per pass), and the reference check's compared frames.
std::vector<Plot> per_frame_plots(const std::string& scenario, const nlohmann::json& summary) {
  std::vector<Plot> plots;
  const nlohmann::json frames = summary.value("frames", nlohmann::json::array());
  std::map<std::string, Plot> scalar, grouped;
  for (const nlohmann::json& f : frames) {
    const double x = number_or_nan(f.value("frame", nlohmann::json()));
    for (const auto& [key, value] : f.items()) {
      if (key == "frame") continue;
      if (value.is_number()) {
        Plot& p = scalar[key];
        if (p.series.empty()) {
          p = {scenario + ": " + key, "frame", key, false, false, {{key, {}, {}, true}}};
        }
        p.series[0].points.emplace_back(x, value.get<double>());
      } else if (value.is_object()) {
        Plot& p = grouped[key];
        if (p.title.empty()) p = {scenario + ": " + key, "frame", key, false, false, {}};
        for (const auto& item : value.items()) {
          // (Not a structured binding: clang 14, the fuzz build's compiler, cannot capture one.)
          const std::string sub = item.key();
          auto it = std::find_if(p.series.begin(), p.series.end(), [&](const PlotSeries& s) { return s.title == sub; });
          if (it == p.series.end()) it = p.series.insert(p.series.end(), PlotSeries{sub, {}, {}, true});
          it->points.emplace_back(x, number_or_nan(item.value()));
        }
      }
    }
  }
  for (auto& [k, p] : grouped) plots.push_back(std::move(p));
  for (auto& [k, p] : scalar) plots.push_back(std::move(p));
  for (const nlohmann::json& c : summary.value("checks", nlohmann::json::array())) {
    const nlohmann::json compared = c.value("figures", nlohmann::json::object()).value("frames", nlohmann::json::array());
    // Only a reference-style check has a list of compared frames ("frames"
    // may also be a count, e.g. cache_lifetime's frames judged).
    if (!compared.is_array() || compared.empty() || !compared[0].is_object() || !compared[0].contains("relmse")) continue;
    Plot p{scenario + ": " + c.value("name", "") + " check error", "frame", "relMSE", false, true, {}};
    for (const char* key : {"relmse", "combined_noise"}) {
      PlotSeries s{key, {}, {}, false};  // few compared frames: points
      for (const nlohmann::json& f : compared)
        s.points.emplace_back(number_or_nan(f.value("frame", nlohmann::json())), number_or_nan(f.value(key, nlohmann::json())));
      p.series.push_back(s);
    }
    plots.push_back(p);
  }
  return plots;
}

std::string flat_figures(const nlohmann::json& j, const std::string& prefix = "") {
  std::string out;
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) out += flat_figures(v, prefix.empty() ? k : prefix + "." + k);
  } else if (j.is_array()) {
    for (const nlohmann::json& item : j) {
      const std::string p = item.is_object() && item.contains("frame") ? fmt::format("{}[frame {}]", prefix, item["frame"].dump()) : prefix;
      out += flat_figures(item, p);
    }
  } else {
    out += "<div><code>" + html_escape(prefix) + "</code> " + html_figure(j) + "</div>";
  }
  return out;
}

std::string checks_table(const nlohmann::json& summary) {
  std::vector<std::vector<std::string>> rows;
  for (const nlohmann::json& c : summary.value("checks", nlohmann::json::array())) {
    const nlohmann::json f = c.value("first_failing_frame", nlohmann::json());
    rows.push_back({html_escape(c.value("name", "")), html_verdict(c.value("verdict", "")),
                    html_escape(c.value("message", "")) + (f.is_null() ? "" : " (first failing frame " + f.dump() + ")"),
                    "<div class=\"small\">" + flat_figures(c.value("figures", nlohmann::json::object())) + "</div>",
                    "<div class=\"small\">" + flat_figures(c.value("limits", nlohmann::json::object())) + "</div>"});
  }
  if (rows.empty()) return "<p class=\"note\">no checks</p>";
  return html_table({"check", "verdict", "message", "figures", "limits"}, rows);
}

std::vector<std::vector<std::string>> regression_rows(const std::string& scenario, const nlohmann::json& deltas) {
  std::vector<std::vector<std::string>> rows;
  for (const nlohmann::json& d : deltas)
    rows.push_back({html_escape(scenario), "<code>" + html_escape(d.value("metric", "")) + "</code>",
                    html_verdict(d.value("status", "")), html_figure(d.value("baseline", nlohmann::json())),
                    html_figure(d.value("measured", nlohmann::json())), html_escape(d.value("tolerance", "")),
                    html_figure(d.value("limit", nlohmann::json()))});
  return rows;
}

const std::vector<std::string> kRegressionHeader = {"scenario", "metric", "status", "baseline", "measured",
                                                    "tolerance", "limit"};

// Previews of every layer of each EXR the checks name as evidence (the
// reference check's gpu / embree / error), linked to the EXR; then captures.
std::string image_section(const std::filesystem::path& scenario_dir, const std::string& scenario_rel,
                          const nlohmann::json& summary) {
  std::string out;
  std::vector<std::string> evidence;
  for (const nlohmann::json& c : summary.value("checks", nlohmann::json::array()))
    for (const nlohmann::json& e : c.value("evidence", nlohmann::json::array())) evidence.push_back(e);
  for (const std::string& e : evidence) {
    if (std::filesystem::path(e).extension() != ".exr") continue;
    const std::filesystem::path exr = scenario_dir / e;
    std::map<std::string, Image> layers;
    try {
      layers = read_exr(exr);
    } catch (const std::exception& ex) {
      out += "<p class=\"note\">" + html_escape(ex.what()) + "</p>";
      continue;
    }
    const std::string href = html_escape(scenario_rel + "/" + e);
    out += fmt::format("<h4>{} <a href=\"{}\">(EXR)</a></h4><div class=\"triplet\">", html_escape(e), href);
    for (const char* name : {"gpu", "embree", "error"}) {
      const auto it = layers.find(name);
      if (it == layers.end()) continue;
      const std::filesystem::path png =
          scenario_dir / "previews" / (std::filesystem::path(e).stem().string() + "_" + name + ".png");
      write_png_preview(png, it->second);
      const std::string caption = std::string(name) == "gpu" ? "output (GPU)"
                                  : std::string(name) == "embree" ? "reference (Embree)"
                                                                  : "error map |gpu-ref|/(|ref|+0.1)";
      // The thumbnail in the page, the full preview beside it.
      out += fmt::format("<figure>{}<figcaption>{}</figcaption></figure>",
                         html_thumbnail(png, scenario_rel + "/previews/" + png.filename().string(),
                                        scenario_rel + " " + e + " " + name),
                         html_escape(caption));
    }
    out += "</div>\n";
  }
  std::string captures;
  for (const nlohmann::json& c : summary.value("captures", nlohmann::json::array())) {
    const std::filesystem::path exr = c.get<std::string>();
    std::filesystem::path png = exr;
    png.replace_extension(".png");
    captures += fmt::format("<figure>{}<figcaption><a href=\"{}\">{}</a></figcaption></figure>",
                            html_thumbnail(scenario_dir / png, scenario_rel + "/" + png.string(),
                                           scenario_rel + " " + exr.string()),
                            html_escape(scenario_rel + "/" + exr.string()), html_escape(exr.string()));
  }
  if (!captures.empty()) out += "<h4>captures</h4><div class=\"triplet\">" + captures + "</div>\n";
  // Each failing check's capture, inspected by the nightly (giharness inspect):
  // the page opened on the output with the check's region outlined where it names one.
  std::string inspect;
  for (const nlohmann::json& f : summary.value("failure_captures", nlohmann::json::array())) {
    if (!f.is_object() || !f.contains("capture") || !f["capture"].is_string()) continue;
    const std::filesystem::path page = std::filesystem::path(f["capture"].get<std::string>()) / "inspect.html";
    if (!std::filesystem::exists(scenario_dir / page)) continue;
    std::string fragment = "#source=output";
    if (f.contains("region") && f["region"].is_array() && f["region"].size() == 4)
      fragment += fmt::format("&region={},{},{},{}", f["region"][0].dump(), f["region"][1].dump(),
                              f["region"][2].dump(), f["region"][3].dump());
    inspect += fmt::format("<li><a class=\"inspect\" href=\"{}\">inspect {} at frame {}</a></li>",
                           html_escape(scenario_rel + "/" + page.string() + fragment),
                           html_escape(f.value("check", std::string("?"))), f.value("frame", 0u));
  }
  if (!inspect.empty()) out += "<h4>failing checks' captures</h4><ul>" + inspect + "</ul>\n";
  return out.empty() ? "<p class=\"note\">no images</p>" : out;
}

// An energy ratio a hair from 1 reads better as a signed percentage.
std::string energy_change(const nlohmann::json& image) {
  if (!image.is_object() || !image.value("energy_ratio", nlohmann::json()).is_number()) return html_figure(nullptr);
  const double percent = (image["energy_ratio"].get<double>() - 1.0) * 100.0;
  return (percent < 0 ? "&minus;" : "+") + html_number(std::fabs(percent)) + " %";
}

// The row's change against its exact baseline (reports/change.h): what
// differs, by how much, and the baseline, current and difference images.
std::string change_section(const std::filesystem::path& out_dir, const nlohmann::json& change) {
  const std::string status = change.value("status", "no_exact_baseline");
  std::string out = "<p>" + html_verdict(status);
  if (change.contains("reason")) out += " " + html_escape(change["reason"].get<std::string>());
  if (status != "changed") return out + "</p>\n";
  out += change.value("fails", false) ? " (fails: --fail-on-change)" : " (not a failure; --fail-on-change makes it one)";
  out += "</p>\n";
  const nlohmann::json image = change.value("image", nlohmann::json());
  std::vector<std::vector<std::string>> rows = {
      {"first frame whose image differs", html_figure(change.value("first_differing_frame", nlohmann::json())) +
                                              " (of " + html_figure(change.value("frames_compared", 0)) + " compared)"},
      {"state buffers that differ after the last frame",
       html_escape(change.value("differing_buffers", nlohmann::json::array()).dump()) + " of " +
           html_figure(change.value("buffers_compared", 0))}};
  for (const char* key : {"added_buffers", "removed_buffers"})
    if (!change.value(key, nlohmann::json::array()).empty())
      rows.push_back({key, html_escape(change[key].dump())});
  if (image.is_object())
    for (const char* key : {"relmse", "energy_ratio", "max_abs_difference", "pixels_differing", "heat_scale"})
      rows.push_back({std::string("final image: ") + key, key == std::string("energy_ratio")
                                                              ? energy_change(image)
                                                              : html_figure(image.value(key, nlohmann::json()))});
  if (change.contains("image_note")) rows.push_back({"note", html_escape(change["image_note"].get<std::string>())});
  out += html_table({"", ""}, rows);
  const nlohmann::json images = change.value("images", nlohmann::json::object());
  if (!images.empty()) {
    out += "<div class=\"triplet\">";
    for (const auto& [key, caption] : std::vector<std::pair<std::string, std::string>>{
             {"baseline", "baseline"},
             {"current", "this run"},
             {"difference", fmt::format("|Δ luminance|, white at {}", html_figure(image.value("heat_scale", 0.0)))}})
      if (images.contains(key))
        out += fmt::format("<figure>{}<figcaption>{}</figcaption></figure>",
                           html_thumbnail(out_dir / images[key].get<std::string>(), images[key].get<std::string>(), key),
                           caption);
    out += "</div>\n";
  }
  return out;
}

double change_relmse(const nlohmann::json& row) {
  const nlohmann::json image = row.value("change", nlohmann::json::object()).value("image", nlohmann::json());
  return image.is_object() ? number_or_nan(image.value("relmse", nlohmann::json())) : std::nan("");
}

// The changed scenarios, largest relMSE against the baseline first (those
// without an image comparison last).
std::string changed_list(const std::vector<nlohmann::json>& rows) {
  std::vector<const nlohmann::json*> changed;
  for (const nlohmann::json& r : rows)
    if (r.value("change", nlohmann::json::object()).value("status", "") == "changed") changed.push_back(&r);
  if (changed.empty()) return "<p>no scenario's bits changed against an exact baseline</p>\n";
  std::stable_sort(changed.begin(), changed.end(), [](const nlohmann::json* a, const nlohmann::json* b) {
    const double ea = change_relmse(*a), eb = change_relmse(*b);
    return std::isnan(eb) ? !std::isnan(ea) : ea > eb;
  });
  std::vector<std::vector<std::string>> table;
  for (const nlohmann::json* r : changed) {
    const nlohmann::json& c = (*r)["change"];
    const nlohmann::json image = c.value("image", nlohmann::json());
    const std::string name = r->value("name", "?");
    table.push_back({"<a href=\"#" + anchor(name) + "\">" + html_escape(name) + "</a>",
                     html_figure(image.is_object() ? image.value("relmse", nlohmann::json()) : nlohmann::json()),
                     energy_change(image),
                     html_figure(c.value("first_differing_frame", nlohmann::json())),
                     html_escape(c.value("differing_buffers", nlohmann::json::array()).dump()),
                     c.value("fails", false) ? html_verdict("fail") : "no"});
  }
  return html_table({"scenario", "relMSE vs baseline", "energy change", "first differing frame", "differing buffers",
                     "fails"},
                    table);
}

// Seeds as a dimension (nightly --seeds, reports/seed_verdicts.h): per
// scenario and check its status over the seeds and the verdict at each seed
// (flaky ones first); "" when no row ran at several seeds.
std::string seeds_section(const nlohmann::json& suite, const std::vector<nlohmann::json>& rows) {
  if (!suite.contains("seeds")) return "";
  std::vector<std::vector<std::string>> flaky, rest;
  for (const nlohmann::json& row : rows) {
    if (!row.contains("seeds")) continue;
    const std::string name = row.value("name", row.value("file", "?"));
    const std::string link = "<a href=\"#" + anchor(name) + "\">" + html_escape(name) + "</a>";
    const nlohmann::json& info = row["seeds"];
    if (info.contains("skipped")) {
      rest.push_back({link, "", html_verdict(row.value("verdict", "?")), "", html_escape(info["skipped"].get<std::string>())});
      continue;
    }
    const nlohmann::json values = info.value("values", nlohmann::json::array());
    for (const nlohmann::json& c : row.value("checks", nlohmann::json::array())) {
      const nlohmann::json verdicts = c.value("seed_verdicts", nlohmann::json::array());
      std::string cells;
      std::size_t passed = 0;
      for (std::size_t k = 0; k < verdicts.size(); ++k) {
        const std::string v = verdicts[k].get<std::string>();
        passed += v == "pass";
        const std::string seed = k < values.size() ? values[k].dump() : "?";
        // html_verdict's span, coloured by the verdict, named by the seed.
        std::string span = html_verdict(v);
        span.replace(span.find('>') + 1, html_escape(v).size(), html_escape(seed + ": " + v));
        cells += span + " ";
      }
      const std::string status = c.value("seed_status", "?");
      (status == "flaky" ? flaky : rest)
          .push_back({link, html_escape(c.value("name", "?")), html_verdict(status),
                      fmt::format("{} of {}", passed, verdicts.size()), "<div class=\"small\">" + cells + "</div>"});
    }
  }
  if (flaky.empty() && rest.empty()) return "";
  const nlohmann::json seeds = suite["seeds"];
  std::string out = fmt::format("<h2>Seeds</h2>\n<p class=\"small\">each scenario at {} seeds ({}); {} flaky checks in {} "
                                "scenarios (a check is flaky when it passes at some seeds and not at others: a "
                                "failure). The baseline comparison and everything below a scenario's heading are "
                                "seed 0's.</p>\n",
                                html_figure(seeds.value("count", nlohmann::json())), html_escape(seeds.value("rule", "")),
                                seeds.value("flaky_checks", nlohmann::json::array()).size(),
                                html_figure(seeds.value("flaky_scenarios", 0)));
  flaky.insert(flaky.end(), rest.begin(), rest.end());
  return out + html_table({"scenario", "check", "over the seeds", "passed at", "verdict per seed"}, flaky, "seeds");
}

// The bug museum (Scenario::bug): catch rate, then each re-created bug,
// missed ones first.
std::string bug_museum(const nlohmann::json& bugs, const std::vector<nlohmann::json>& rows) {
  std::vector<std::vector<std::string>> table;
  const bool seeded = bugs.contains("seed_runs");
  for (bool caught : {false, true})
    for (const nlohmann::json& row : rows) {
      if (!row.contains("bug") || row["bug"].value("caught", false) != caught) continue;
      const nlohmann::json& b = row["bug"];
      std::string checks;
      for (const nlohmann::json& c : b.value("caught_by", nlohmann::json::array()))
        checks += (checks.empty() ? "" : ", ") + c.get<std::string>();
      const nlohmann::json seeds = b.value("seeds", nlohmann::json());
      const bool flaky = !caught && seeds.is_object() && seeds.value("caught", 0) > 0;
      std::vector<std::string> cells = {
          "<a href=\"#" + anchor(row.value("name", "?")) + "\">" + html_escape(row.value("name", "?")) + "</a>",
          html_escape(b.value("source", "")), html_escape(b.value("symptom", "")), html_escape(checks),
          html_verdict(caught ? "caught" : flaky ? "flaky" : "missed")};
      if (seeded) cells.push_back(seeds.is_object() ? html_escape(seeds.value("text", "")) : "");
      table.push_back(cells);
    }
  std::string head = fmt::format("<h2>Bug museum</h2>\n<p>catch rate <b>{:.0f} %</b>: {} caught, {} missed",
                                 100.0 * bugs.value("catch_rate", 0.0), bugs.value("caught", 0), bugs.value("missed", 0));
  if (seeded)
    head += fmt::format(", {} flaky (caught at some seeds only); over all seed runs {:.0f} % ({} of {})",
                        bugs.value("flaky", 0), 100.0 * bugs.value("seed_catch_rate", 0.0),
                        bugs.value("seed_runs_caught", 0), bugs.value("seed_runs", 0));
  std::vector<std::string> header = {"scenario", "bug", "symptom", "caught by", ""};
  if (seeded) header.push_back("over the seeds");
  return head + "</p>\n" + html_table(header, table);
}

// The folder of the plots beside the page, and a plot's SVG file as the page
// links it: relative to the page's folder.
constexpr const char* kPlotsFolder = "plots";
std::string plot_src(const PlotResult& plot) { return std::string(kPlotsFolder) + "/" + plot.file.filename().string(); }

// The scene a path tracer's point of the scatter was measured at (its label
// names only its spp): the run whose equal_time peer has the point's figures.
std::string peer_scene(const std::vector<NamedSummary>& runs, double ms, double relmse) {
  for (const NamedSummary& r : runs) {
    const nlohmann::json eq = r.summary->value("equal_time", nlohmann::json::object());
    if (!eq.is_object()) continue;
    for (const char* key : {"gpu_path_tracer", "embree"}) {
      const nlohmann::json peer = eq.value(key, nlohmann::json::object());
      if (peer.is_object() && number_or_nan(peer.value("ms", nlohmann::json())) == ms &&
          number_or_nan(peer.value("relmse", nlohmann::json())) == relmse)
        return r.name;
    }
  }
  return "";
}

// The speed-against-error scatter for the page: no label drawn (with dozens
// of scenarios they pile up), each point's scenario and figures its hover
// text; and the same points as a table (the legend, readable without a mouse).
std::string speed_against_error_points(Plot& scatter, const std::vector<NamedSummary>& runs) {
  scatter.hover_labels = true;
  std::vector<std::vector<std::string>> rows;
  for (PlotSeries& series : scatter.series) {
    for (std::size_t k = 0; k < series.points.size() && k < series.labels.size(); ++k) {
      const auto [ms, relmse] = series.points[k];
      std::string scene = series.labels[k];
      if (scene.size() > 4 && scene.compare(scene.size() - 4, 4, " spp") == 0) {  // a path tracer's point
        const std::string at = peer_scene(runs, ms, relmse);
        scene = at.empty() ? scene : at + " (" + scene + ")";
      }
      series.labels[k] = fmt::format("{}: {} ms/frame, relMSE {} ({})", scene, html_number(ms), html_number(relmse),
                                     series.title);
      rows.push_back({html_escape(series.title), html_escape(scene), "<span class=\"num\">" + html_number(ms) + "</span>",
                      "<span class=\"num\">" + html_number(relmse) + "</span>"});
    }
  }
  if (rows.empty()) return "";
  return fmt::format("<details><summary>the plot's {} points (hover a point for its scenario)</summary>\n", rows.size()) +
         html_table({"series", "scenario", "ms/frame", "relMSE"}, rows, "points") + "</details>\n";
}

}  // namespace

std::filesystem::path write_nightly_report(const std::filesystem::path& out_dir, const nlohmann::json& suite) {
  struct Page {
    nlohmann::json row, summary;
    std::size_t first_plot = 0, plot_count = 0;
  };
  std::vector<Page> pages;
  std::vector<Plot> plots;
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array())) {
    Page page{row, nlohmann::json::object()};
    if (row.contains("summary")) {
      try {
        page.summary = nlohmann::json::parse(std::ifstream(out_dir / row["summary"].get<std::string>()));
      } catch (const std::exception& e) {
        spdlog::warn("report: cannot read {}: {}", row["summary"].dump(), e.what());
      }
    }
    const std::string name = row.value("name", row.value("file", "?"));
    if (page.summary.is_object() && !page.summary.empty()) {
      const std::vector<Plot> mine = per_frame_plots(name, page.summary);
      page.first_plot = plots.size();
      page.plot_count = mine.size();
      plots.insert(plots.end(), mine.begin(), mine.end());
    }
    pages.push_back(page);
  }
  std::vector<NamedSummary> runs;
  for (const Page& p : pages)
    if (p.summary.is_object() && !p.summary.empty()) runs.push_back({p.row.value("name", p.row.value("file", "?")), &p.summary});
  const std::size_t scatter_id = plots.size();
  plots.push_back(speed_against_error_plot(runs));
  const std::string scatter_points = speed_against_error_points(plots.back(), runs);
  const nlohmann::json history = suite.value("timing_history", nlohmann::json::array());
  const std::size_t trend_id = plots.size();
  if (!history.empty()) plots.push_back(timing_trend_plot(history, timing_history_entry(suite, "tonight")));
  const std::vector<PlotResult> drawn = render_plots(plots, out_dir / kPlotsFolder);

  std::string body = "<h1>giharness nightly</h1>\n";
  const nlohmann::json device = suite.value("device", nlohmann::json::object());
  std::vector<std::vector<std::string>> info = {
      {"suite", html_escape(suite.value("suite", ""))},
      {"verdict", html_verdict(suite.value("verdict", "?"))},
      {"exit code", html_figure(suite.value("exit_code", nlohmann::json()))},
      {"device", html_escape(device.value("name", "?")) + " &mdash; " + html_escape(device.value("driver_info", ""))},
      {"device class", html_escape(suite.value("device_class", "?"))},
      {"baseline", html_escape(suite.value("baseline_dir", "")) + " (" +
                       html_escape(suite.value("baseline_status", "none")) + ")"},
      {"wall time", html_figure(suite.value("wall_seconds", nlohmann::json())) + " s"},
      {"build", html_escape(suite.value("build", nlohmann::json::object()).dump())}};
  if (suite.contains("shard")) info.push_back({"shard", html_escape(suite["shard"].dump())});
  if (suite.value("jobs", 1) > 1)
    info.push_back({"jobs", fmt::format("{} scenarios at once: their timing and speed-against-error figures were "
                                        "measured on a loaded machine",
                                        suite["jobs"].get<int>())});
  if (suite.value("interrupted", false)) info.push_back({"interrupted", html_verdict("interrupted")});
  body += html_table({"", ""}, info);

  std::vector<std::vector<std::string>> overview, all_regressions;
  for (const Page& p : pages) {
    const std::string name = p.row.value("name", p.row.value("file", "?"));
    std::size_t passed = 0, total = 0;
    for (const nlohmann::json& c : p.row.value("checks", nlohmann::json::array())) {
      ++total;
      passed += c.value("verdict", "") == "pass";
    }
    const nlohmann::json deltas = p.row.value("regressions", nlohmann::json::array());
    std::size_t regressed = 0;
    for (const nlohmann::json& d : deltas) regressed += d.value("status", "") != "improved";
    const nlohmann::json timings = p.summary.is_object() ? p.summary.value("timings", nlohmann::json::object()) : nlohmann::json::object();
    overview.push_back({"<a href=\"#" + anchor(name) + "\">" + html_escape(name) + "</a>",
                        html_verdict(p.row.value("verdict", p.row.value("status", "?"))),
                        fmt::format("{}/{} pass", passed, total),
                        fmt::format("{}", regressed) + " (" + html_escape(p.row.value("baseline_status", "no baseline")) + ")",
                        html_verdict(p.row.value("change", nlohmann::json::object()).value("status", "no_exact_baseline")),
                        "<span class=\"num\">" + html_figure(timings.value("total_mean_ms", nlohmann::json())) + "</span>",
                        html_figure(p.row.value("wall_seconds", nlohmann::json()))});
    for (auto& r : regression_rows(name, deltas)) all_regressions.push_back(r);
  }
  std::vector<nlohmann::json> rows;
  for (const Page& p : pages) rows.push_back(p.row);
  const nlohmann::json tally = suite.value("changes", nlohmann::json::object());
  body += fmt::format("<h2>Changed against the exact baseline</h2>\n<p class=\"small\">{} unchanged, {} changed, {} "
                      "without an exact baseline (same device class, device and driver)</p>\n",
                      html_figure(tally.value("unchanged", 0)), html_figure(tally.value("changed", 0)),
                      html_figure(tally.value("no_exact_baseline", 0))) +
          changed_list(rows);
  if (suite.contains("bugs")) body += bug_museum(suite["bugs"], rows);
  body += "<h2>Overview</h2>\n" +
          html_table({"scenario", "verdict", "checks", "regressions", "bits", "GPU ms/frame", "wall s"}, overview);
  body += seeds_section(suite, rows);
  body += "<h2>Figures against the baseline's tolerances</h2>\n";
  body += all_regressions.empty() ? "<p>no figure outside its tolerance</p>\n"
                                  : html_table(kRegressionHeader, all_regressions, "regressions");
  body += "<h2>Speed against error</h2>\n" + html_plot_inline(drawn[scatter_id], "speed against error") +
          scatter_points + speed_against_error_tables(runs);
  const nlohmann::json timing = suite.value("timing", nlohmann::json::object());
  body += fmt::format("<h2>Timing against the baseline</h2>\n<p class=\"small\">{} scenarios regressed, {} improved, "
                      "{} unchanged, {} not compared ({} of them because the machine was loaded); {}</p>\n",
                      html_figure(timing.value("regressed", 0)), html_figure(timing.value("improved", 0)),
                      html_figure(timing.value("unchanged", 0)), html_figure(timing.value("not_compared", 0)),
                      html_figure(timing.value("loaded", 0)),
                      timing.value("fatal", false) ? "timing is fatal (--fail-on-timing: exit bit 4)"
                                                   : "reported only: timing never fails this night");
  const auto timing_rows = timing_overview_rows(suite);
  body += timing_rows.empty() ? "<p>no pass outside its interval</p>\n" : html_table(kTimingOverviewHeader, timing_rows);
  if (!history.empty())
    body += fmt::format("<h3>Trend over the last {} nights and this one</h3>\n", history.size()) +
            html_plot_file(drawn[trend_id], plot_src(drawn[trend_id]), "timing trend");

  for (const Page& p : pages) {
    const std::string name = p.row.value("name", p.row.value("file", "?"));
    body += "<h2 id=\"" + anchor(name) + "\">" + html_escape(name) + " " +
            html_verdict(p.row.value("verdict", p.row.value("status", "?"))) + "</h2>\n";
    if (p.row.contains("error")) body += "<p>" + html_escape(p.row["error"].get<std::string>()) + "</p>\n";
    if (!p.summary.is_object() || p.summary.empty()) continue;
    // The settings a reader compares runs by; the full profile is in summary.json.
    const nlohmann::json resolved = p.summary.value("resolved", nlohmann::json::object());
    std::string settings;
    for (const char* key : {"resolution", "frames", "seed", "mode", "samples_per_frame", "profile", "backend", "overrides"})
      if (resolved.contains(key)) settings += std::string(settings.empty() ? "" : ", ") + key + " " + resolved[key].dump();
    body += "<p class=\"small\">" + html_escape(p.summary["scenario"].value("file", "")) + " &mdash; " +
            html_escape(settings) + " &mdash; <a href=\"" + html_escape(p.row["summary"].get<std::string>()) +
            "\">summary.json</a></p>\n";
    if (p.row.contains("seeds") && p.row["seeds"].contains("runs")) {
      std::string links;
      for (const nlohmann::json& r : p.row["seeds"]["runs"])
        links += (links.empty() ? "" : ", ") +
                 (r.contains("summary") ? "<a href=\"" + html_escape(r["summary"].get<std::string>()) + "\">seed " +
                                              html_escape(r.value("seed", nlohmann::json()).dump()) + "</a>"
                                        : "seed " + html_escape(r.value("seed", nlohmann::json()).dump())) +
                 " " + html_verdict(r.value("verdict", "?"));
      body += "<p class=\"small\">seed 0's run below; at each seed: " + links + "</p>\n";
    }
    body += "<h3>Checks</h3>\n" + checks_table(p.summary);
    const nlohmann::json deltas = p.row.value("regressions", nlohmann::json::array());
    if (!deltas.empty()) body += "<h3>Figures outside the baseline's tolerances</h3>\n" + html_table(kRegressionHeader, regression_rows(name, deltas));
    if (p.row.contains("change")) body += "<h3>Bits against the exact baseline</h3>\n" + change_section(out_dir, p.row["change"]);
    if (p.row.contains("timing")) body += "<h3>Timing against the baseline</h3>\n" + timing_section(p.row["timing"]);
    body += "<h3>Per-frame curves</h3>\n";
    for (std::size_t i = p.first_plot; i < p.first_plot + p.plot_count; ++i)
      body += html_plot_file(drawn[i], plot_src(drawn[i]), plots[i].title) + "\n";
    const std::filesystem::path rel = std::filesystem::path(p.row["summary"].get<std::string>()).parent_path();
    body += "<h3>Images</h3>\n" + image_section(out_dir / rel, rel.string(), p.summary);
  }
  const std::filesystem::path report = out_dir / "report.html";
  write_text_file(report, html_page("giharness nightly: " + suite.value("suite", ""), body));
  return report;
}

}  // namespace gi
