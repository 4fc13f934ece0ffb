// Each check's statistical model (CheckModel, core/check_catalog.h): every
// declared check states what it estimates, its noise estimate and its
// false-alarm rate; the schema's description and every result's limits carry
// it; and every check has a scene in the seed soak (tests/alarm_rates/),
// which counts its alarms over seeds against that rate.
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "core/check_catalog.h"
#include "tests/alarm_rates/alarm_rate_scenes.h"
#include "tests/test_support.h"

namespace gi {
namespace {

TEST(CheckModels, EveryCheckStatesItsModelInTheSchema) {
  std::ifstream in(test::source_dir() / "scenarios/schema.json");
  const nlohmann::json schema = nlohmann::json::parse(in);
  ASSERT_GE(declared_checks().size(), 20u);
  for (const CheckDeclaration& d : declared_checks()) {
    SCOPED_TRACE(d.name);
    const CheckModel& m = d.model;
    EXPECT_FALSE(m.estimates.empty());
    EXPECT_FALSE(m.noise.empty());
    EXPECT_FALSE(m.false_alarm.empty());
    // Exact checks, and only they, promise no false alarm at all.
    EXPECT_EQ(m.basis == CheckModel::Basis::exact, m.false_alarm_rate == 0.0);
    EXPECT_LE(m.false_alarm_rate, 0.01) << "a verdict wrong at more than 1 % of seeds is not a verdict";
    const std::string description = schema["$defs"]["check_" + d.name].value("description", "");
    EXPECT_NE(description.find(std::string("Statistical model (") + to_string(m.basis) + "): estimates " + m.estimates),
              std::string::npos)
        << description;
    EXPECT_NE(description.find("False-alarm rate: " + m.false_alarm), std::string::npos);
  }
}

TEST(CheckModels, EveryCheckHasASeedSoakSceneThatRunsIt) {
  std::set<std::string> declared, soaked;
  for (const CheckDeclaration& d : declared_checks()) declared.insert(d.name);
  for (const test::AlarmRateScene& s : test::alarm_rate_scenes()) {
    SCOPED_TRACE(s.check + " in " + s.scenario);
    EXPECT_TRUE(soaked.insert(s.check).second) << "listed twice";
    const nlohmann::json scenario = test::read_json(test::source_dir() / s.scenario);
    bool runs_it = false;
    for (const nlohmann::json& c : scenario.value("checks", nlohmann::json::array())) runs_it |= c.value("name", "") == s.check;
    EXPECT_TRUE(runs_it) << "the soak's scene does not run the check";
  }
  EXPECT_EQ(soaked, declared);
}

TEST(CheckModels, AllowedAlarmsAreTheBinomialsUpperQuantile) {
  EXPECT_EQ(test::allowed_alarms(10, 0.0), 0u);  // an exact check: none
  // 0.27 %: one alarm in 10 runs has a 2.7 % chance, two 3.3e-4.
  EXPECT_EQ(test::allowed_alarms(10, 0.0027), 1u);
  EXPECT_EQ(test::allowed_alarms(10, 1e-12), 0u);
  EXPECT_EQ(test::allowed_alarms(1000, 0.001), 5u);  // mean 1; P(X > 5) = 5.9e-4, P(X > 4) = 3.6e-3
  EXPECT_EQ(test::allowed_alarms(4, 0.5), 4u);
}

TEST(CheckModels, TheSummaryStatesEachVerdictsFalseAlarmRate) {
  // The furnace runs without a device: a second's run.
  test::TempDir dir("check-models");
  const auto r = test::run_giharness("run " + (test::source_dir() / "scenarios/furnace_bevy_main_brdf.json").string() + " --out " + dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json furnace = test::check_result(dir.path(), "furnace");
  EXPECT_EQ(furnace["limits"].value("false_alarm_rate", ""), "exact: " + find_declared_check("furnace")->model.false_alarm);
}

}  // namespace
}  // namespace gi
