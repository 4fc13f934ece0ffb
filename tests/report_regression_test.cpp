// Baseline comparison and JUnit, in process (no GPU): each tolerance kind
// fires on the change it exists for and stays quiet inside its tolerance.
#include <gtest/gtest.h>

#include "reports/junit.h"
#include "reports/regression.h"

namespace gi {
namespace {

ScenarioFigures figures(std::map<std::string, double> f, std::map<std::string, std::string> v = {}) {
  ScenarioFigures s;
  s.figures = std::move(f);
  s.verdicts = std::move(v);
  return s;
}

const FigureDelta* find(const BaselineComparison& c, const std::string& metric) {
  for (const FigureDelta& d : c.deltas)
    if (d.metric == metric) return &d;
  return nullptr;
}

// Times are the timing verdict's (reports/timing_verdict.h): the default
// rules leave them out of the correctness comparison entirely.
TEST(ReportRegression, TimesAreNotCorrectnessByDefault) {
  const ScenarioFigures base = figures({{"timings/total_median_ms", 10.0}, {"timings/passes/a/median_ms", 0.1}});
  const BaselineComparison c =
      compare_to_baseline(base, figures({{"timings/total_median_ms", 40.0}}), default_tolerance_rules());
  EXPECT_EQ(c.compared, 0u);
  EXPECT_TRUE(c.deltas.empty());
}

// A "time" rule (as a tolerances.json may give) still judges one as a ratio.
TEST(ReportRegression, TimeIsARatioWithANoiseMargin) {
  std::vector<ToleranceRule> rules = {{"timings/*", {ToleranceKind::time, 1.5, 0.25, 0.0, 0.0}}};
  rules.insert(rules.end(), default_tolerance_rules().begin(), default_tolerance_rules().end());
  const ScenarioFigures base = figures({{"timings/total_mean_ms", 10.0}, {"timings/passes/a/mean_ms", 0.1}});
  // 1.4x and a tiny pass at 3x (inside the 0.25 ms margin): no regression.
  EXPECT_EQ(compare_to_baseline(base, figures({{"timings/total_mean_ms", 14.0}, {"timings/passes/a/mean_ms", 0.3}}), rules)
                .regressions(), 0u);
  const BaselineComparison slow =
      compare_to_baseline(base, figures({{"timings/total_mean_ms", 16.0}, {"timings/passes/a/mean_ms", 0.1}}), rules);
  ASSERT_EQ(slow.regressions(), 1u);
  const FigureDelta* d = find(slow, "timings/total_mean_ms");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->baseline, 10.0);
  EXPECT_EQ(d->measured, 16.0);
  EXPECT_DOUBLE_EQ(d->limit.get<double>(), 15.25);
  EXPECT_NE(d->tolerance.find("1.5"), std::string::npos);
  // Much faster is reported, never failed.
  const BaselineComparison fast =
      compare_to_baseline(base, figures({{"timings/total_mean_ms", 4.0}, {"timings/passes/a/mean_ms", 0.1}}), rules);
  EXPECT_EQ(fast.regressions(), 0u);
  ASSERT_NE(find(fast, "timings/total_mean_ms"), nullptr);
  EXPECT_EQ(find(fast, "timings/total_mean_ms")->status, "improved");
}

TEST(ReportRegression, LuminanceRegressesBothWaysAndErrorsOnlyUpwards) {
  const auto& rules = default_tolerance_rules();
  const ScenarioFigures base = figures({{"frames/last/mean_luminance", 1.0}, {"checks/reference/frame_7/relmse", 0.01}});
  EXPECT_EQ(compare_to_baseline(base, figures({{"frames/last/mean_luminance", 1.01}, {"checks/reference/frame_7/relmse", 0.0105}}), rules)
                .regressions(), 0u);
  const BaselineComparison dim =
      compare_to_baseline(base, figures({{"frames/last/mean_luminance", 0.95}, {"checks/reference/frame_7/relmse", 0.01}}), rules);
  ASSERT_EQ(dim.regressions(), 1u);
  EXPECT_EQ(dim.deltas[0].metric, "frames/last/mean_luminance");
  EXPECT_EQ(compare_to_baseline(base, figures({{"frames/last/mean_luminance", 1.05}, {"checks/reference/frame_7/relmse", 0.01}}), rules)
                .regressions(), 1u);
  EXPECT_EQ(compare_to_baseline(base, figures({{"frames/last/mean_luminance", 1.0}, {"checks/reference/frame_7/relmse", 0.02}}), rules)
                .regressions(), 1u);
  const BaselineComparison better =
      compare_to_baseline(base, figures({{"frames/last/mean_luminance", 1.0}, {"checks/reference/frame_7/relmse", 0.005}}), rules);
  EXPECT_EQ(better.regressions(), 0u);
  ASSERT_EQ(better.deltas.size(), 1u);
  EXPECT_EQ(better.deltas[0].status, "improved");
}

TEST(ReportRegression, VerdictAndMissingFigureRegress) {
  const auto& rules = default_tolerance_rules();
  const ScenarioFigures base = figures({{"frames/last/x", 1.0}}, {{"reference", "pass"}});
  EXPECT_EQ(compare_to_baseline(base, figures({{"frames/last/x", 1.0}}, {{"reference", "pass"}}), rules).regressions(), 0u);
  const BaselineComparison broke = compare_to_baseline(base, figures({{"frames/last/x", 1.0}}, {{"reference", "inconclusive"}}), rules);
  ASSERT_EQ(broke.regressions(), 1u);
  EXPECT_EQ(broke.deltas[0].metric, "checks/reference/verdict");
  EXPECT_EQ(broke.deltas[0].measured, "inconclusive");
  const BaselineComparison gone = compare_to_baseline(base, figures({}, {{"reference", "pass"}}), rules);
  ASSERT_EQ(gone.regressions(), 1u);
  EXPECT_EQ(gone.deltas[0].status, "missing");
}

TEST(ReportRegression, ExtractsTimingsCheckFiguresAndLastFrame) {
  const nlohmann::json summary = nlohmann::json::parse(R"json({
    "timings": {"total_mean_ms": 2.0, "passes": {"trace": {"mean_ms": 1.5, "median_ms": 1.4, "p95_ms": 1.9}}},
    "checks": [{"name": "reference", "verdict": "pass", "figures": {"frames": [{"frame": 7, "relmse": 0.02, "reason": ""}]}}],
    "frames": [{"frame": 0, "mean_luminance": 0.1}, {"frame": 1, "mean_luminance": 0.2, "pass_ms": {"trace": 1.0}}]})json");
  const ScenarioFigures f = extract_figures(summary);
  EXPECT_EQ(f.figures.at("timings/total_median_ms"), 1.4);
  EXPECT_EQ(f.figures.count("timings/total_mean_ms"), 0u);
  EXPECT_EQ(f.figures.at("timings/passes/trace/median_ms"), 1.4);
  EXPECT_EQ(f.figures.count("timings/passes/trace/p95_ms"), 0u);
  EXPECT_EQ(f.figures.at("checks/reference/frames/frame_7/relmse"), 0.02);
  EXPECT_EQ(f.figures.at("frames/last/mean_luminance"), 0.2);
  EXPECT_EQ(f.figures.count("frames/last/pass_ms/trace"), 0u);
  EXPECT_EQ(f.verdicts.at("reference"), "pass");
  // With per-frame sums (summary.json's timings.frame), their median is the
  // total: the last frame's state hash, one frame long, adds nothing to it.
  nlohmann::json with_frames = summary;
  with_frames["timings"]["passes"]["state_hash"] = {{"median_ms", 30.0}};
  with_frames["timings"]["frame"] = {{"gpu_pass_sum_median_ms", 1.5}};
  EXPECT_EQ(extract_figures(with_frames).figures.at("timings/total_median_ms"), 1.5);
}

TEST(ReportRegression, JunitMarksTheCaseOfARegressionFailed) {
  const nlohmann::json suite = nlohmann::json::parse(R"json({"suite": "s", "scenarios": [
    {"name": "a", "status": "complete", "exit_code": 1, "baseline_status": "compared",
     "checks": [{"name": "finite", "verdict": "pass"}, {"name": "reference", "verdict": "pass"}],
     "regressions": [{"metric": "frames/last/mean_luminance", "status": "regressed", "baseline": 1.0,
                      "measured": 0.95, "tolerance": "baseline +/- (2% + 1e-06)"}]},
    {"name": "b", "status": "complete", "exit_code": 0, "baseline_status": "compared",
     "checks": [{"name": "finite", "verdict": "pass"}]}]})json");
  const std::string xml = junit_xml(suite);
  EXPECT_NE(xml.find("tests=\"5\" failures=\"1\""), std::string::npos) << xml;
  const std::size_t a_baseline = xml.find("classname=\"a\" name=\"baseline\"");
  ASSERT_NE(a_baseline, std::string::npos) << xml;
  const std::size_t failure = xml.find("<failure", a_baseline);
  ASSERT_NE(failure, std::string::npos);
  EXPECT_LT(failure, xml.find("</testcase>", a_baseline));
  EXPECT_NE(xml.find("frames/last/mean_luminance regressed: baseline 1.0, measured 0.95", failure), std::string::npos) << xml;
}

}  // namespace
}  // namespace gi
