// The luminance_range check (checks/luminance_range_check.cpp) fires on
// the frame that goes black, passes without it, and refuses a range upside
// down as bad input at its path.
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/scenario.h"
#include "replay/run_scenario.h"
#include "tests/test_support.h"

namespace gi {
namespace {

const std::filesystem::path kScenario = test::source_dir() / "tests/data/scenarios/good/luminance_range_light_off.json";

CheckResult run_check(const Scenario& s, const std::filesystem::path& out) {
  RunOptions o;
  o.out_dir = out;
  o.quiet = true;
  const RunResult r = run_scenario(s, o);
  for (const CheckResult& c : r.checks)
    if (c.name == "luminance_range") return c;
  ADD_FAILURE() << "no luminance_range result";
  return {};
}

TEST(LuminanceRangeCheck, FailsAtTheFrameThatGoesBlackAndPassesWithoutIt) {
  const test::TempDir dir("luminance-range");
  const CheckResult dark = run_check(load_scenario(kScenario), dir.path() / "dark");
  EXPECT_EQ(dark.verdict, Verdict::fail) << dark.message;
  ASSERT_TRUE(dark.first_failing_frame);
  EXPECT_EQ(*dark.first_failing_frame, 4u);
  EXPECT_EQ(dark.figures["frames_outside"], 2u);  // frames 4 and 5
  EXPECT_EQ(dark.figures["lowest_mean_luminance"], 0.0);

  nlohmann::json lit = load_scenario(kScenario).raw;
  lit["events"] = nlohmann::json::array();
  const CheckResult pass = run_check(parse_scenario(lit, kScenario), dir.path() / "lit");
  EXPECT_EQ(pass.verdict, Verdict::pass) << pass.message;
  EXPECT_EQ(pass.figures["frames_judged"], 6u);
  EXPECT_GT(pass.figures["lowest_mean_luminance"].get<double>(), 0.01);
}

TEST(LuminanceRangeCheck, ARangeUpsideDownIsBadInputAtItsPath) {
  nlohmann::json doc = load_scenario(kScenario).raw;
  doc["checks"][0]["min"] = 2.0;
  doc["checks"][0]["max"] = 1.0;
  const test::TempDir dir("luminance-range-bad");
  try {
    run_check(parse_scenario(doc, kScenario), dir.path());
    FAIL() << "min > max accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/checks/0/max") << e.what();
  }
}

}  // namespace
}  // namespace gi
