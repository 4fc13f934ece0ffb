#include "reports/suite_report.h"

#include <algorithm>

#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "reports/junit.h"
#include "reports/nightly_report.h"
#include "reports/seed_verdicts.h"
#include "reports/timing_report.h"

namespace gi {

int suite_exit_code(const nlohmann::json& suite) {
  int worst = 0;
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array()))
    worst = std::max(worst, row.value("exit_code", 0));
  if (suite.value("interrupted", false)) worst = 3;
  // Timing is its own bit, and only when asked for (reports/timing_report.h).
  if (suite.value("fail_on_timing", false) && !timing_tally(suite)["scenarios_regressed"].empty())
    worst |= kTimingExitBit;
  return worst;
}

int finish_suite(const std::filesystem::path& out_dir, nlohmann::json& suite, const std::filesystem::path& junit) {
  suite["timing"] = timing_tally(suite);
  const int code = suite_exit_code(suite);
  suite["exit_code"] = code;
  // Change detection's tally (reports/change.h), largest difference first in the report.
  nlohmann::json changes = {{"unchanged", 0}, {"changed", 0}, {"no_exact_baseline", 0}};
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array()))
    if (row.contains("change")) {
      const std::string status = row["change"].value("status", "no_exact_baseline");
      if (changes.contains(status)) changes[status] = changes[status].get<int>() + 1;
    }
  suite["changes"] = changes;
  // The bug museum's tally (Scenario::bug): present when any scenario re-creates a bug.
  // With --seeds (reports/seed_verdicts.h) a bug is caught when caught at
  // every seed, flaky when at some; the rate over all its seed runs beside.
  int caught = 0, missed = 0, flaky = 0, seed_runs = 0, seed_runs_caught = 0;
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array()))
    if (row.contains("bug")) {
      const nlohmann::json seeds = row["bug"].value("seeds", nlohmann::json());
      if (seeds.is_object()) {
        seed_runs += seeds.value("count", 0);
        seed_runs_caught += seeds.value("caught", 0);
      }
      if (row["bug"].value("caught", false)) ++caught;
      else if (seeds.is_object() && seeds.value("caught", 0) > 0) ++flaky;
      else ++missed;
    }
  if (caught + missed + flaky > 0) {
    suite["bugs"] = {{"caught", caught}, {"missed", missed},
                     {"catch_rate", double(caught) / double(caught + missed + flaky)}};
    if (seed_runs > 0) {
      suite["bugs"]["flaky"] = flaky;
      suite["bugs"]["seed_runs"] = seed_runs;
      suite["bugs"]["seed_runs_caught"] = seed_runs_caught;
      suite["bugs"]["seed_catch_rate"] = double(seed_runs_caught) / double(seed_runs);
    }
  } else {
    suite.erase("bugs");
  }
  // Seeds as a dimension: the flaky checks of the night.
  const nlohmann::json seed_checks = seed_tally(suite);
  if (!seed_checks.is_null()) {
    if (!suite.contains("seeds") || !suite["seeds"].is_object()) suite["seeds"] = nlohmann::json::object();
    suite["seeds"].update(seed_checks);
  }
  const int correctness = code & ~kTimingExitBit;
  suite["verdict"] = suite.value("interrupted", false) ? "interrupted"
                     : code == kTimingExitBit          ? "timing_regressed"
                     : correctness == 0                ? "pass"
                     : correctness == 1                ? "fail"
                                                       : "error";
  const std::filesystem::path junit_path = junit.empty() ? out_dir / "junit.xml" : junit;
  suite["junit"] = junit_path.string();
  suite["report"] = (out_dir / "report.html").string();
  write_json_file(out_dir / "summary.json", suite);
  write_text_file(junit_path, junit_xml(suite));
  write_nightly_report(out_dir, suite);
  return code;
}

}  // namespace gi
