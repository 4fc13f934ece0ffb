#include "reports/regression.h"

#include <fnmatch.h>

#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "core/errors.h"
#include "reports/json_figures.h"

namespace gi {
namespace {

Tolerance worse_up(double rel, double abs) { return {ToleranceKind::higher_is_worse, 1.0, 0.0, rel, abs}; }
Tolerance both_ways(double rel, double abs) { return {ToleranceKind::two_sided, 1.0, 0.0, rel, abs}; }
Tolerance ignored() { return {ToleranceKind::ignore, 1.0, 0.0, 0.0, 0.0}; }

ToleranceKind parse_kind(const std::string& s, const std::string& file, const std::string& path) {
  if (s == "time") return ToleranceKind::time;
  if (s == "higher_is_worse") return ToleranceKind::higher_is_worse;
  if (s == "two_sided") return ToleranceKind::two_sided;
  if (s == "ignore") return ToleranceKind::ignore;
  throw InputError(file, path, "one of \"time\", \"higher_is_worse\", \"two_sided\", \"ignore\"");
}

}  // namespace

double Tolerance::upper_limit(double b) const {
  if (kind == ToleranceKind::time) return ratio * b + margin;
  return b + abs + rel * std::fabs(b);
}

std::string Tolerance::describe() const {
  switch (kind) {
    case ToleranceKind::time: return fmt::format("<= {:g} x baseline + {:g} ms", ratio, margin);
    case ToleranceKind::higher_is_worse: return fmt::format("<= baseline + {:g}% + {:g}", rel * 100.0, abs);
    case ToleranceKind::two_sided: return fmt::format("baseline +/- ({:g}% + {:g})", rel * 100.0, abs);
    case ToleranceKind::ignore: return "not compared";
  }
  return "";
}

// Why these numbers: times are not compared here by default. They are the
// timing verdict's (reports/timing_verdict.h): per-frame samples, calibrated
// on lavapipe, a separate verdict that never fails a night alone unless asked.
// A tolerances.json may still hold a "time" rule (ratio × baseline + margin)
// for a figure it wants judged as correctness. Accuracy figures are bit-identical on one device and driver; the tolerances
// leave room for another machine of the same class (a Mesa or LLVM update)
// while catching a 5% energy loss or a 10% relMSE increase.
const std::vector<ToleranceRule>& default_tolerance_rules() {
  static const std::vector<ToleranceRule> rules = {
      {"timings/*", ignored()},
      {"*/reference_seconds", ignored()},  // the Embree side, often a cache hit
      {"*nonfinite*", worse_up(0.0, 0.0)},
      {"*relmse*", worse_up(0.10, 1e-6)},
      {"*noise*", worse_up(0.10, 1e-6)},
      {"*_error", worse_up(0.10, 1e-6)},
      {"*_sigma", worse_up(0.25, 1e-6)},
      {"*luminance*", both_ways(0.02, 1e-6)},
      {"*energy_ratio", both_ways(0.01, 1e-6)},
      {"*", both_ways(0.05, 1e-9)},
  };
  return rules;
}

std::vector<ToleranceRule> load_tolerance_rules(const std::filesystem::path& baseline_dir) {
  std::vector<ToleranceRule> rules;
  const std::filesystem::path file = baseline_dir / "tolerances.json";
  if (std::filesystem::exists(file)) {
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(std::ifstream(file));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(file.string(), "", std::string("valid JSON (") + e.what() + ")");
    }
    if (!doc.is_array()) throw InputError(file.string(), "", "a list of tolerance rules");
    for (std::size_t i = 0; i < doc.size(); ++i) {
      const nlohmann::json& r = doc[i];
      const std::string path = "/" + std::to_string(i);
      if (!r.is_object() || !r.contains("pattern") || !r["pattern"].is_string() || !r.contains("kind") ||
          !r["kind"].is_string())
        throw InputError(file.string(), path, "an object with string \"pattern\" and \"kind\"");
      ToleranceRule rule;
      rule.pattern = r["pattern"];
      rule.tolerance.kind = parse_kind(r["kind"], file.string(), path + "/kind");
      for (const char* key : {"ratio", "margin", "rel", "abs"})
        if (r.contains(key) && !r[key].is_number())
          throw InputError(file.string(), path + "/" + key, "a number");
      rule.tolerance.ratio = r.value("ratio", 1.0);
      rule.tolerance.margin = r.value("margin", 0.0);
      rule.tolerance.rel = r.value("rel", 0.0);
      rule.tolerance.abs = r.value("abs", 0.0);
      rules.push_back(rule);
    }
  }
  const auto& defaults = default_tolerance_rules();
  rules.insert(rules.end(), defaults.begin(), defaults.end());
  return rules;
}

const Tolerance& tolerance_for(const std::vector<ToleranceRule>& rules, const std::string& figure) {
  for (const ToleranceRule& r : rules)
    if (fnmatch(r.pattern.c_str(), figure.c_str(), 0) == 0) return r.tolerance;
  return default_tolerance_rules().back().tolerance;
}

nlohmann::json FigureDelta::to_json() const {
  return {{"metric", metric}, {"status", status},       {"baseline", baseline},
          {"measured", measured}, {"tolerance", tolerance}, {"limit", limit}};
}

std::size_t BaselineComparison::regressions() const {
  std::size_t n = 0;
  for (const FigureDelta& d : deltas) n += d.regression();
  return n;
}

BaselineComparison compare_to_baseline(const ScenarioFigures& baseline, const ScenarioFigures& measured,
                                       const std::vector<ToleranceRule>& rules) {
  BaselineComparison out;
  for (const auto& [check, verdict] : baseline.verdicts) {
    const std::string metric = "checks/" + check + "/verdict";
    const auto it = measured.verdicts.find(check);
    ++out.compared;
    if (it == measured.verdicts.end()) {
      out.deltas.push_back({metric, "missing", verdict, nullptr, "check must still run", nullptr});
    } else if (verdict == "pass" && it->second != "pass") {
      out.deltas.push_back({metric, "regressed", verdict, it->second, "verdict must stay pass", nullptr});
    } else if (verdict != "pass" && it->second == "pass") {
      out.deltas.push_back({metric, "improved", verdict, it->second, "verdict must stay pass", nullptr});
    }
  }
  for (const auto& [metric, b] : baseline.figures) {
    const Tolerance& tol = tolerance_for(rules, metric);
    if (tol.kind == ToleranceKind::ignore) continue;
    ++out.compared;
    const auto it = measured.figures.find(metric);
    if (it == measured.figures.end()) {
      out.deltas.push_back({metric, "missing", json_figure(b), nullptr, tol.describe(), nullptr});
      continue;
    }
    const double m = it->second;
    const double hi = tol.upper_limit(b);
    if (tol.kind == ToleranceKind::two_sided) {
      const double lo = b - (hi - b);
      if (m > hi || m < lo)
        out.deltas.push_back({metric, "regressed", json_figure(b), json_figure(m), tol.describe(),
                              json_figure(m > hi ? hi : lo)});
      continue;
    }
    if (m > hi) {
      out.deltas.push_back({metric, "regressed", json_figure(b), json_figure(m), tol.describe(), json_figure(hi)});
    } else {
      // Improvement: as far below the baseline as a regression would be above.
      const double lo = tol.kind == ToleranceKind::time ? (b - tol.margin) / tol.ratio : b - (hi - b);
      if (m < lo && hi > b)
        out.deltas.push_back({metric, "improved", json_figure(b), json_figure(m), tol.describe(), json_figure(lo)});
    }
  }
  return out;
}

}  // namespace gi
