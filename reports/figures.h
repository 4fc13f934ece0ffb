// The figures a nightly compares against its baseline (docs/design.md §10): every
// number of a scenario's summary.json that says how fast or how accurate the
// run was, flattened to "path/like/this" names, and the check verdicts.
#pragma once
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace gi {

struct ScenarioFigures {
  std::map<std::string, double> figures;       // e.g. "timings/passes/reference_path_trace/mean_ms"
  std::map<std::string, std::string> verdicts;  // check name → "pass" | "fail" | "inconclusive"

  nlohmann::json to_json() const;
  static ScenarioFigures from_json(const nlohmann::json& j);
};

// From a scenario summary.json (replay/run_scenario.cpp):
// - timings/passes/<pass>/median_ms, and timings/total_median_ms: the median
//   of the per-frame pass sums (timings/frame), else the sum of the medians;
// - checks/<check>/<figure>, with per-frame arrays named by frame
//   (checks/reference/frame_63/relmse);
// - frames/last/<key> for every number of the last per-frame record except
//   the pass timings (already summarised), so curves the pipeline adds later
//   (active cells, lag, …) are compared without code changes here.
// Booleans, strings and non-finite figures are left out.
ScenarioFigures extract_figures(const nlohmann::json& scenario_summary);

// "llvmpipe-2threads", "nvidia-h100-80gb-hbm3": the device's name up to its
// first '(' (drivers append versions there), lower case, with lavapipe's
// thread count, because times only compare within one class. A run that
// used no device (count-only scenarios) is of class "any-device".
std::string device_class(const nlohmann::json& device);

}  // namespace gi
