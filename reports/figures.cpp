#include "reports/figures.h"

#include <cctype>
#include <cmath>
#include <thread>

namespace gi {
namespace {

void add_number(ScenarioFigures& out, const std::string& name, const nlohmann::json& v) {
  if (!v.is_number()) return;  // strings ("nan", "inf") and booleans are not compared as numbers
  const double d = v.get<double>();
  if (std::isfinite(d)) out.figures[name] = d;
}

// Numbers of an object, recursing into objects and into arrays of records
// that carry a "frame" (named frame_<N>); other arrays are left out.
void flatten(ScenarioFigures& out, const std::string& prefix, const nlohmann::json& j) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) flatten(out, prefix + "/" + key, value);
  } else if (j.is_array()) {
    for (const nlohmann::json& item : j)
      if (item.is_object() && item.contains("frame") && item["frame"].is_number_unsigned())
        flatten(out, prefix + "/frame_" + std::to_string(item["frame"].get<unsigned>()), item);
  } else {
    add_number(out, prefix, j);
  }
}

}  // namespace

nlohmann::json ScenarioFigures::to_json() const { return {{"figures", figures}, {"verdicts", verdicts}}; }

ScenarioFigures ScenarioFigures::from_json(const nlohmann::json& j) {
  ScenarioFigures f;
  f.figures = j.at("figures").get<std::map<std::string, double>>();
  f.verdicts = j.at("verdicts").get<std::map<std::string, std::string>>();
  return f;
}

ScenarioFigures extract_figures(const nlohmann::json& s) {
  ScenarioFigures out;
  if (s.contains("timings")) {
    const nlohmann::json& t = s["timings"];
    // Medians: one slow frame (a pipeline compiled at its first dispatch, a
    // descheduled thread) moves the mean and p95 of a short run far more than
    // a real slowdown of a pass moves its median.
    const nlohmann::json passes = t.value("passes", nlohmann::json::object());
    double total = 0;
    for (const auto& [pass, stats] : passes.items()) {
      const nlohmann::json median = stats.value("median_ms", nlohmann::json());
      add_number(out, "timings/passes/" + pass + "/median_ms", median);
      total += median.is_number() ? median.get<double>() : 0.0;
    }
    // The median of the per-frame sums where the run has it: a pass of one
    // frame (the last frame's state hash) does not add its whole time.
    const nlohmann::json frame_sum = t.value("frame", nlohmann::json::object()).value("gpu_pass_sum_median_ms", nlohmann::json());
    if (frame_sum.is_number()) total = frame_sum.get<double>();
    if (!passes.empty()) out.figures["timings/total_median_ms"] = total;
  }
  for (const nlohmann::json& c : s.value("checks", nlohmann::json::array())) {
    const std::string name = c.value("name", "?");
    out.verdicts[name] = c.value("verdict", "fail");
    flatten(out, "checks/" + name, c.value("figures", nlohmann::json::object()));
  }
  const nlohmann::json frames = s.value("frames", nlohmann::json::array());
  if (!frames.empty()) {
    nlohmann::json last = frames.back();
    last.erase("pass_ms");
    last.erase("calibration_ms");  // times: the timing verdict's (reports/timing_verdict.h)
    last.erase("cpu_schedule");
    last.erase("frame");
    flatten(out, "frames/last", last);
  }
  return out;
}

std::string device_class(const nlohmann::json& device) {
  if (!device.is_object() || device.empty()) return "any-device";
  std::string name = device.value("name", "unknown-device");
  name = name.substr(0, name.find('('));
  std::string slug;
  for (char ch : name) {
    if (std::isalnum(static_cast<unsigned char>(ch)))
      slug += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    else if (!slug.empty() && slug.back() != '-')
      slug += '-';
  }
  while (!slug.empty() && slug.back() == '-') slug.pop_back();
  if (slug.empty()) slug = "unknown-device";
  if (slug == "llvmpipe") {
    std::string threads = device.value("lp_num_threads", "default");
    if (threads == "default") threads = std::to_string(std::thread::hardware_concurrency());
    slug += "-" + threads + "threads";
  }
  return slug;
}

}  // namespace gi
