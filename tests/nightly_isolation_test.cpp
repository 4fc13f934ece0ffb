// Nothing one scenario does takes the night down: the nightly runs
// each scenario in a process of its own, so a hostile file, a crash, a hang
// and a lost device each become that scenario's verdict, the others pass,
// and the summary, the report and JUnit are written. The faults are forced
// with GIHARNESS_TEST_FAULT=<kind>@<frame>:<scenario> (replay/test_faults.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "tests/test_support.h"

namespace gi {
namespace {

// The tiny suite's three scenarios: tiny_cornell, tiny_light_toggle (the one
// the faults aim at), tiny_no_blocks; `middle` replaces the second file.
std::filesystem::path suite_of_three(const std::filesystem::path& dir, const std::string& middle = "") {
  const std::filesystem::path suite = dir / "suite", tiny = test::source_dir() / "tests/data/suites/tiny";
  std::filesystem::create_directories(suite);
  std::filesystem::copy_file(tiny / "tiny_cornell.json", suite / "1_tiny_cornell.json");
  if (middle.empty())
    std::filesystem::copy_file(tiny / "tiny_light_toggle.json", suite / "2_tiny_light_toggle.json");
  else
    std::ofstream(suite / "2_hostile.json", std::ios::binary) << middle;
  std::filesystem::copy_file(tiny / "tiny_no_blocks.json", suite / "3_tiny_no_blocks.json");
  return suite;
}

struct Night {
  test::CommandResult result;
  nlohmann::json summary;
};

Night nightly(const test::TempDir& dir, const std::filesystem::path& suite, const std::string& env,
              const std::string& extra = "") {
  const std::filesystem::path out = dir.path() / "out";
  Night n;
  n.result = test::run_giharness("nightly --suite " + suite.string() + " --out " + out.string() + " --baseline " +
                                     (dir.path() / "none").string() + " " + extra,
                                 env);
  n.summary = test::read_json(out / "summary.json");
  return n;
}

// Scenarios 1 and 3 pass; the middle one ends as `verdict` with `reason` in
// its error, its log's tail kept; the suite's exit code is `code`; the report
// and JUnit (an <error>, not a <failure>) are there.
void expect_middle_only(const test::TempDir& dir, const Night& n, const std::string& verdict, const std::string& reason,
                        int code) {
  ASSERT_EQ(n.summary["scenarios"].size(), 3u) << n.result.output;
  EXPECT_EQ(n.result.exit_code, code) << n.result.output;
  EXPECT_FALSE(n.summary.value("interrupted", false));
  for (int i : {0, 2}) EXPECT_EQ(n.summary["scenarios"][i]["verdict"], "pass") << n.summary["scenarios"][i].dump(1);
  const nlohmann::json& row = n.summary["scenarios"][1];
  EXPECT_EQ(row["status"], "complete");
  EXPECT_EQ(row["verdict"], verdict) << row.dump(1);
  EXPECT_NE(row.value("error", "").find(reason), std::string::npos) << row.dump(1);
  EXPECT_TRUE(row.contains("log_tail")) << row.dump(1);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "out" / row.value("log", "?"))) << row.dump(1);
  const std::string junit = test::read_text(dir.path() / "out/junit.xml");
  EXPECT_NE(junit.find("<error"), std::string::npos) << junit;
  EXPECT_NE(test::read_text(dir.path() / "out/report.html").find(verdict), std::string::npos);
}

TEST(NightlyIsolation, AHostileScenarioIsBadInputAndTheNightGoesOn) {
  const test::TempDir dir("isolation-hostile");
  const std::string deep = "{\"name\": \"deep\", \"description\": " + std::string(60000, '[') +
                           std::string(60000, ']') + ", \"scene\": {\"generator\": \"cornell_box\"}, " +
                           "\"resolution\": [8, 8], \"frames\": 1}";
  const Night n = nightly(dir, suite_of_three(dir.path(), deep), "");
  expect_middle_only(dir, n, "bad_input", "nested at most 256 deep", 2);
  EXPECT_EQ(n.summary["scenarios"][1]["exit_code"], 2);
}

TEST(NightlyIsolation, ACrashIsThatScenariosVerdict) {
  const test::TempDir dir("isolation-crash");
  const Night n = nightly(dir, suite_of_three(dir.path()), "GIHARNESS_TEST_FAULT=crash@3:tiny_light_toggle");
  expect_middle_only(dir, n, "crashed", "SIGSEGV", 3);
}

TEST(NightlyIsolation, AHangEndsAsTimeout) {
  const test::TempDir dir("isolation-hang");
  // The tiny scenarios take about a second each on lavapipe; the hung one is
  // stopped after 8 s.
  const Night n = nightly(dir, suite_of_three(dir.path()), "GIHARNESS_TEST_FAULT=hang@3:tiny_light_toggle",
                          "--scenario-timeout 8");
  expect_middle_only(dir, n, "timeout", "no result within 8 s", 3);
  EXPECT_LT(n.summary["scenarios"][1]["wall_seconds"].get<double>(), 20.0);
}

// A lost device is that scenario's verdict, and --resume runs it again.
TEST(NightlyIsolation, ADeviceLossIsThatScenariosVerdictAndResumeRetriesIt) {
  const test::TempDir dir("isolation-device");
  const std::filesystem::path suite = suite_of_three(dir.path());
  const Night n = nightly(dir, suite, "GIHARNESS_TEST_FAULT=device_lost@3:tiny_light_toggle");
  expect_middle_only(dir, n, "device_error", "device lost (forced", 3);

  const Night resumed = nightly(dir, suite, "", "--resume");
  EXPECT_EQ(resumed.result.exit_code, 0) << resumed.result.output;
  EXPECT_NE(resumed.result.output.find("resuming: 2 of 3"), std::string::npos) << resumed.result.output;
  for (const nlohmann::json& row : resumed.summary["scenarios"]) EXPECT_EQ(row["verdict"], "pass") << row.dump(1);
}

TEST(NightlyIsolation, AScenariosOwnTimeoutWinsOverTheSuites) {
  const test::TempDir dir("isolation-own-timeout");
  std::string toggle = test::read_text(test::source_dir() / "tests/data/suites/tiny/tiny_light_toggle.json");
  toggle.insert(toggle.find('{') + 1, "\n  \"timeout_seconds\": 3,");
  const Night n = nightly(dir, suite_of_three(dir.path(), toggle), "GIHARNESS_TEST_FAULT=hang@3:tiny_light_toggle",
                          "--scenario-timeout 600");
  expect_middle_only(dir, n, "timeout", "no result within 3 s", 3);
}

// The offset of the first line of `output` that holds both `a` and `b`.
std::size_t line_with(const std::string& output, const std::string& a, const std::string& b) {
  for (std::size_t start = 0; start < output.size();) {
    const std::size_t end = std::min(output.find('\n', start), output.size());
    const std::string line = output.substr(start, end - start);
    if (line.find(a) != std::string::npos && line.find(b) != std::string::npos) return start;
    start = end + 1;
  }
  return std::string::npos;
}

// --jobs 2 runs two scenarios at once: the third ends while the hung second
// still runs (one at a time, it could not start before the second ended),
// and every row keeps the suite's order and the verdict it has alone.
TEST(NightlyIsolation, JobsRunScenariosSideBySideInTheSuitesOrder) {
  const test::TempDir dir("isolation-jobs");
  const Night n = nightly(dir, suite_of_three(dir.path()), "GIHARNESS_TEST_FAULT=hang@3:tiny_light_toggle",
                          "--scenario-timeout 8 --jobs 2");
  expect_middle_only(dir, n, "timeout", "no result within 8 s", 3);
  EXPECT_EQ(n.summary["jobs"], 2);
  const std::size_t third = line_with(n.result.output, "[3/3] tiny_no_blocks", "pass");
  const std::size_t second = line_with(n.result.output, "[2/3]", "timeout");
  ASSERT_NE(third, std::string::npos) << n.result.output;
  ASSERT_NE(second, std::string::npos) << n.result.output;
  EXPECT_LT(third, second) << n.result.output;
  EXPECT_NE(n.result.output.find("2 scenarios at a time"), std::string::npos) << n.result.output;
}

// Baselines keep timing samples and a timing verdict needs a quiet machine:
// neither is asked of a night that runs scenarios side by side.
TEST(NightlyIsolation, JobsRefuseWhatMeasuresTime) {
  const test::TempDir dir("isolation-jobs-refuse");
  for (const char* flag : {"--update-baseline", "--add-timing-run", "--fail-on-timing"}) {
    const test::CommandResult r = test::run_giharness("nightly --suite " + suite_of_three(dir.path() / flag).string() +
                                                          " --out " + (dir.path() / "out").string() + " --jobs 2 " + flag,
                                                      "");
    EXPECT_EQ(r.exit_code, 2) << flag << r.output;
    EXPECT_NE(r.output.find("one scenario at a time"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "out/summary.json")) << flag;
  }
}

}  // namespace
}  // namespace gi
