// Comparing a scenario's figures with its baseline (docs/design.md §10): per-metric
// tolerances chosen by name pattern, first match wins.
//
// - time figures (timings/…) are not compared by default: the timing verdict
//   does that from per-frame samples (reports/timing_verdict.h). A rule of
//   kind "time" in tolerances.json compares one as a ratio with a noise
//   margin: a regression is measured > ratio × baseline + margin_ms; a run
//   that fast in the other direction is reported as improved, never failed;
// - error figures (relMSE, noise, errors, non-finite counts) only regress
//   upwards: measured > baseline + abs + rel × |baseline|;
// - level figures (luminance, energy ratio, anything else) regress both
//   ways: |measured − baseline| > abs + rel × |baseline|;
// - a check that passed in the baseline and does not now is a regression;
// - a figure or check the baseline has and the run lacks is a regression
//   (the output changed shape: update the baseline on purpose).
//
// A baseline folder may hold tolerances.json, a list of rules of the same
// form ({"pattern", "kind", "ratio", "margin", "rel", "abs"}) tried before the
// defaults, so a scenario with a known noisy figure says so next to its data.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/figures.h"

namespace gi {

enum class ToleranceKind { time, higher_is_worse, two_sided, ignore };

struct Tolerance {
  ToleranceKind kind = ToleranceKind::two_sided;
  double ratio = 1.0;   // time: allowed measured / baseline
  double margin = 0.0;  // time: absolute noise margin (ms)
  double rel = 0.0;     // accuracy: relative tolerance
  double abs = 0.0;     // accuracy: absolute tolerance

  // The largest (or, two-sided, the farthest) value that still passes.
  double upper_limit(double baseline) const;
  std::string describe() const;  // "≤ 1.5 × baseline + 0.25 ms", "± 2% + 1e-06"
};

struct ToleranceRule {
  std::string pattern;  // fnmatch pattern over the figure name
  Tolerance tolerance;
};

const std::vector<ToleranceRule>& default_tolerance_rules();
// Rules from <baseline_dir>/tolerances.json (none if absent) then the defaults.
// InputError naming the file and JSON path on a malformed rule.
std::vector<ToleranceRule> load_tolerance_rules(const std::filesystem::path& baseline_dir);
const Tolerance& tolerance_for(const std::vector<ToleranceRule>& rules, const std::string& figure);

// One compared figure or check verdict that did not stay within tolerance.
struct FigureDelta {
  std::string metric;           // figure name, or "checks/<name>/verdict"
  std::string status;           // "regressed", "improved", "missing"
  nlohmann::json baseline;      // number or verdict string
  nlohmann::json measured;      // number, verdict string, or null when missing
  std::string tolerance;        // Tolerance::describe(), or "verdict must stay pass"
  nlohmann::json limit;         // the value the measurement was held to (null for verdicts)
  bool regression() const { return status != "improved"; }
  nlohmann::json to_json() const;
};

struct BaselineComparison {
  std::vector<FigureDelta> deltas;  // regressions and improvements only
  std::size_t compared = 0;         // figures and verdicts held to a tolerance
  std::size_t regressions() const;
};

BaselineComparison compare_to_baseline(const ScenarioFigures& baseline, const ScenarioFigures& measured,
                                       const std::vector<ToleranceRule>& rules);

}  // namespace gi
