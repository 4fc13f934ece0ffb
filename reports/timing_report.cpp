#include "reports/timing_report.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <map>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/json_input.h"
#include "reports/html_page.h"
#include "reports/timing_verdict.h"

namespace gi {
namespace {

std::string interval_text(const nlohmann::json& s) {
  const nlohmann::json iv = s.value("interval", nlohmann::json::array());
  if (!iv.is_array() || iv.size() != 2 || !iv[0].is_number() || iv[0].get<double>() <= 0) return "&ndash;";
  return "[" + html_figure(iv[0]) + ", " + html_figure(iv[1]) + "]";
}

// How many runs the baseline kept of this series and their spread (slowest
// median over fastest): what a slowdown must exceed besides min_ratio.
std::string baseline_runs_text(const nlohmann::json& s) {
  const std::size_t runs = s.value("baseline_runs", 0u);
  if (runs <= 1) return runs == 1 ? "1" : "&ndash;";
  return fmt::format("{} (&times;{})", runs, html_figure(s.value("spread", nlohmann::json())));
}

std::vector<std::string> series_cells(const nlohmann::json& s) {
  return {html_escape(s.value("name", "?")),
          "<span class=\"num\">" + html_figure(s.value("baseline_ms", nlohmann::json())) + "</span>",
          "<span class=\"num\">" + html_figure(s.value("measured_ms", nlohmann::json())) + "</span>",
          "<span class=\"num\">" + html_figure(s.value("ratio", nlohmann::json())) + "</span>",
          interval_text(s), baseline_runs_text(s), html_verdict(s.value("verdict", "?"))};
}

// A pointer into `timing` (not into a copy: value() would return one).
const nlohmann::json* pipeline_total(const nlohmann::json& timing) {
  if (!timing.contains("series") || !timing["series"].is_array()) return nullptr;
  for (const nlohmann::json& s : timing["series"])
    if (s.is_object() && s.value("name", "") == kPipelineTotal) return &s;
  return nullptr;
}

}  // namespace

const std::vector<std::string> kTimingOverviewHeader = {"scenario", "series", "baseline ms", "measured ms", "ratio",
                                                         "interval", "baseline runs (spread)", "verdict"};

nlohmann::json timing_tally(const nlohmann::json& suite) {
  nlohmann::json t = {{"regressed", 0}, {"improved", 0}, {"unchanged", 0}, {"not_compared", 0}, {"loaded", 0},
                      {"scenarios_regressed", nlohmann::json::array()},
                      {"fatal", suite.value("fail_on_timing", false)}};
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array())) {
    if (!row.contains("timing")) continue;
    const std::string v = row["timing"].value("verdict", "not_compared");
    const std::string key = t.contains(v) ? v : "not_compared";
    t[key] = t[key].get<int>() + 1;
    // Of those not compared, the ones a loaded machine kept from a verdict.
    const nlohmann::json series = row["timing"].value("series", nlohmann::json::array());
    if (v == "not_compared" &&
        std::any_of(series.begin(), series.end(), [](const nlohmann::json& s) { return s.value("verdict", "") == "loaded"; }))
      t["loaded"] = t["loaded"].get<int>() + 1;
    if (v == "regressed") t["scenarios_regressed"].push_back(row.value("name", "?"));
  }
  return t;
}

std::string timing_section(const nlohmann::json& timing) {
  std::string out = fmt::format(
      "<p class=\"small\">timing {} &mdash; samples in {}; ratio of medians run/baseline with its {:.1f} % "
      "block-bootstrap interval; regressed when the interval lies above {} (times the spread of the baseline's runs) "
      "and the pass is {} ms slower</p>\n",
      html_verdict(timing.value("verdict", "not_compared")), html_escape(timing.value("unit", "?")),
      100.0 * timing.value("interval_coverage", 0.0), html_figure(timing.value("min_ratio", nlohmann::json())),
      html_figure(timing.value("min_abs_ms", nlohmann::json())));
  if (timing.contains("typical_ratio"))
    out += fmt::format("<p class=\"small\">passes are judged relative to the others: their ratio and interval are "
                       "divided by the typical (median) pass ratio, {}; the pipeline total is judged as measured</p>\n",
                       html_figure(timing["typical_ratio"]));
  if (timing.contains("reason")) out += "<p>" + html_escape(timing["reason"].get<std::string>()) + "</p>\n";
  // How loaded each side was: frames that waited too long for a CPU are not judged.
  const nlohmann::json load = timing.value("load", nlohmann::json::object());
  for (const char* side : {"baseline", "run"})
    if (load.contains(side))
      out += fmt::format("<p class=\"small\">{} load: median {} % of the CPU time wanted spent waiting for a CPU; {} "
                         "of {} frames left out (over {} %)</p>\n",
                         side, html_figure(100.0 * load[side].value("median_wait_share", 0.0)),
                         html_figure(load[side].value("loaded_frames", 0)), html_figure(load[side].value("frames", 0)),
                         html_figure(100.0 * load[side].value("max_wait_share", 0.0)));
  std::vector<std::vector<std::string>> rows;
  for (const nlohmann::json& s : timing.value("series", nlohmann::json::array())) rows.push_back(series_cells(s));
  if (!rows.empty())
    out += html_table({"series", "baseline ms", "measured ms", "ratio", "interval", "baseline runs (spread)", "verdict"}, rows);
  return out;
}

std::vector<std::vector<std::string>> timing_overview_rows(const nlohmann::json& suite) {
  std::vector<std::vector<std::string>> rows;
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array())) {
    if (!row.contains("timing")) continue;
    for (const nlohmann::json& s : row["timing"].value("series", nlohmann::json::array())) {
      const std::string v = s.value("verdict", "");
      if (v != "regressed" && v != "improved") continue;
      std::vector<std::string> cells = series_cells(s);
      cells.insert(cells.begin(), html_escape(row.value("name", "?")));
      rows.push_back(cells);
    }
  }
  return rows;
}

std::string utc_timestamp() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const long ms = long(std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
  return fmt::format("{}.{:03d}Z", text, ms);
}

void attach_timing_history(nlohmann::json& suite, const std::filesystem::path& dir, std::size_t nights) {
  if (dir.empty()) return;
  suite["timing_history"] = read_timing_history(dir, nights);
  suite["history_dir"] = dir.string();
}

void record_timing_history(const nlohmann::json& suite, const std::filesystem::path& dir, const std::string& started_utc) {
  // An interrupted night's timings are a part of a night: not a point of the trend.
  if (dir.empty() || suite.value("interrupted", false)) return;
  write_timing_history(dir, timing_history_entry(suite, started_utc));
}

nlohmann::json timing_history_entry(const nlohmann::json& suite, const std::string& started_utc) {
  nlohmann::json scenarios = nlohmann::json::object();
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array())) {
    if (!row.contains("name") || !row["name"].is_string()) continue;
    nlohmann::json e = {{"verdict", row.value("verdict", "?")}};
    if (row.contains("timing")) {
      e["timing"] = row["timing"].value("verdict", "not_compared");
      if (const nlohmann::json* total = pipeline_total(row["timing"]))
        e[kPipelineTotal] = {{"ratio", total->value("ratio", nlohmann::json())},
                             {"interval", total->value("interval", nlohmann::json())},
                             {"measured_ms", total->value("measured_ms", nlohmann::json())}};
    }
    scenarios[row["name"].get<std::string>()] = e;
  }
  return {{"started", started_utc},
          {"suite", suite.value("suite", "")},
          {"device_class", suite.value("device_class", "")},
          {"verdict", suite.value("verdict", "")},
          {"scenarios", scenarios}};
}

nlohmann::json read_timing_history(const std::filesystem::path& dir, std::size_t nights) {
  nlohmann::json out = nlohmann::json::array();
  if (!std::filesystem::is_directory(dir)) return out;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());  // names are UTC times: sorted is oldest first
  if (files.size() > nights) files.erase(files.begin(), files.end() - std::ptrdiff_t(nights));
  for (const std::filesystem::path& f : files) out.push_back(read_json_input(f, "a nightly history entry"));
  return out;
}

void write_timing_history(const std::filesystem::path& dir, const nlohmann::json& entry) {
  std::string name = entry.value("started", "unknown");
  std::replace(name.begin(), name.end(), ':', '-');  // a file name on every file system
  std::filesystem::create_directories(dir);
  write_json_file(dir / (name + ".json"), entry);
}

Plot timing_trend_plot(const nlohmann::json& history, const nlohmann::json& tonight) {
  Plot plot{"pipeline time against the baseline, per night (1.0: the baseline's median)", "night",
            "ratio of medians", false, false, {}};
  std::map<std::string, PlotSeries> by_scenario;
  nlohmann::json nights = history;
  nights.push_back(tonight);
  for (std::size_t n = 0; n < nights.size(); ++n) {
    const nlohmann::json scenarios = nights[n].value("scenarios", nlohmann::json::object());  // outlives items()
    for (const auto& [name, e] : scenarios.items()) {
      const nlohmann::json total = e.value(kPipelineTotal, nlohmann::json::object());
      const nlohmann::json ratio = total.value("ratio", nlohmann::json());
      if (!ratio.is_number()) continue;
      PlotSeries& s = by_scenario[name];
      s.title = name;
      s.points.push_back({double(n + 1), ratio.get<double>()});
    }
  }
  for (auto& [name, s] : by_scenario) plot.series.push_back(std::move(s));
  return plot;
}

}  // namespace gi
