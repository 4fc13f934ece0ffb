// The seed soak: each check on a pipeline without its bug (its scene in
// alarm_rate_scenes.h), at N seeds of the scenario's seed set (`giharness run
// --seeds N`), its alarms counted against the false-alarm rate its model
// states (CheckModel). A check fails here when it raised more alarms than
// that rate allows but for a 0.1 % chance (allowed_alarms): its limit or its
// noise estimate is wrong. Each scene runs once for all the checks it holds.
//
// A command of its own, outside ctest's default tier (hours on lavapipe at
// 10 seeds): `build/tests/giharness_alarm_rates`, with GIHARNESS_ALARM_SEEDS
// (default 10) and GIHARNESS_ALARM_OUT (default a temporary folder, removed)
// to keep the runs. A scene whose <out>/<scene>/summary.json is already there
// at that many seeds is read, not run again: a soak resumes where it stopped
// (empty the folder after changing the pipeline). --gtest_filter picks checks
// (`*/motion`). Each test prints the verdict and message at every seed.
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "core/check_catalog.h"
#include "tests/alarm_rates/alarm_rate_scenes.h"
#include "tests/test_support.h"

namespace gi {
namespace {

std::uint32_t soak_seeds() {
  const char* s = std::getenv("GIHARNESS_ALARM_SEEDS");
  return s && *s ? static_cast<std::uint32_t>(std::stoul(s)) : 10u;
}

const std::filesystem::path& soak_out() {
  static test::TempDir temp("alarm-rates");
  static const std::filesystem::path out = [] {
    const char* o = std::getenv("GIHARNESS_ALARM_OUT");
    return o && *o ? std::filesystem::path(o) : temp.path();
  }();
  return out;
}

// `run --seeds N`'s combined summary of a scene, run once per process.
const nlohmann::json& seed_summary(const std::string& scenario) {
  static std::map<std::string, nlohmann::json> done;
  if (auto it = done.find(scenario); it != done.end()) return it->second;
  const std::filesystem::path out = soak_out() / std::filesystem::path(scenario).stem();
  if (std::filesystem::exists(out / "summary.json")) {
    nlohmann::json kept = test::read_json(out / "summary.json");
    if (kept.value("seeds", nlohmann::json::array()).size() == soak_seeds()) return done[scenario] = kept;
  }
  const auto r = test::run_giharness("run " + (test::source_dir() / scenario).string() + " --seeds " +
                                     std::to_string(soak_seeds()) + " --out " + out.string());
  nlohmann::json summary;
  if (std::filesystem::exists(out / "summary.json")) summary = test::read_json(out / "summary.json");
  else ADD_FAILURE() << scenario << ": no summary (exit " << r.exit_code << ")\n" << r.output;
  return done[scenario] = summary;
}

class AlarmRates : public ::testing::TestWithParam<test::AlarmRateScene> {};

TEST_P(AlarmRates, AlarmsOverSeedsWithinTheStatedRate) {
  const test::AlarmRateScene& scene = GetParam();
  const CheckDeclaration* declared = find_declared_check(scene.check);
  ASSERT_NE(declared, nullptr);
  const nlohmann::json& summary = seed_summary(scene.scenario);
  ASSERT_TRUE(summary.contains("checks")) << scene.scenario;
  const nlohmann::json* check = nullptr;
  for (const nlohmann::json& c : summary["checks"])
    if (c.value("name", "") == scene.check) check = &c;
  ASSERT_NE(check, nullptr) << scene.scenario << " gave no result of " << scene.check;
  const nlohmann::json& verdicts = (*check)["verdicts"];
  const nlohmann::json& seeds = summary["seeds"];
  std::uint32_t alarms = 0;
  for (std::size_t k = 0; k < verdicts.size(); ++k) {
    const std::string v = verdicts[k];
    alarms += v != "pass";  // an inconclusive verdict is not a pass either
    std::cout << scene.check << "\t" << scene.scenario << "\tseed " << seeds[k] << "\t" << v << "\t"
              << (*check)["per_seed"][k].value("message", "") << "\n";
  }
  const double rate = declared->model.false_alarm_rate;
  const std::uint32_t allowed = test::allowed_alarms(static_cast<std::uint32_t>(verdicts.size()), rate);
  std::cout << scene.check << ": " << alarms << " alarm(s) in " << verdicts.size() << " seeds; stated rate " << rate
            << " (" << to_string(declared->model.basis) << ") allows " << allowed << "\n";
  RecordProperty("alarms", static_cast<int>(alarms));
  RecordProperty("seeds", static_cast<int>(verdicts.size()));
  EXPECT_LE(alarms, allowed) << scene.check << " in " << scene.scenario << ": " << declared->model.false_alarm;
}

INSTANTIATE_TEST_SUITE_P(Checks, AlarmRates, ::testing::ValuesIn(test::alarm_rate_scenes()),
                         [](const ::testing::TestParamInfo<test::AlarmRateScene>& i) { return i.param.check; });

}  // namespace
}  // namespace gi
