// The bug museum: a scenario with a "bug" key re-creates a known
// bug; the nightly calls it caught when every check it names fails, missed
// otherwise (exit 1, a JUnit failure), and prints the suite's catch rate.
// One caught and one missed bug from the same broken pipeline: ReSTIR GI
// with its jacobian rejection off, which the jacobian check catches and the
// finite check cannot.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json broken_corners(const std::string& name, const nlohmann::json& bug) {
  nlohmann::json doc =
      test::read_json(test::source_dir() / "scenarios/expected_failures/gi_corners_no_jacobian_rejection.json");
  doc.erase("$schema");
  doc["name"] = name;
  doc["frames"] = 6;
  doc["checks"] = {{{"name", "finite"}}, {{"name", "jacobian"}}};
  doc["bug"] = bug;
  return doc;
}

TEST(BugMuseum, NightlyReportsCaughtAndMissedBugsAndTheCatchRate) {
  test::TempDir dir("bug-museum");
  const auto suite = dir.path() / "bugs";
  std::filesystem::create_directories(suite);
  std::ofstream(suite / "caught.json")
      << broken_corners("caught", {{"source", "test#1"}, {"symptom", "J above the limit"}, {"caught_by", {"jacobian"}}})
             .dump(1);
  std::ofstream(suite / "missed.json")
      << broken_corners("missed", {{"source", "test#2"}, {"symptom", "J above the limit"}, {"caught_by", {"finite"}}})
             .dump(1);
  const auto out = dir.path() / "out";
  const test::CommandResult r = test::run_giharness("nightly --suite " + suite.string() + " --baseline " +
                                                    (dir.path() / "baselines").string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;  // one bug missed
  EXPECT_NE(r.output.find("catch rate 50 %"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("missed bug: missed (test#2)"), std::string::npos) << r.output;

  const nlohmann::json summary = test::read_json(out / "summary.json");
  ASSERT_TRUE(summary.contains("bugs")) << summary.dump(1);
  EXPECT_EQ(summary["bugs"]["caught"], 1);
  EXPECT_EQ(summary["bugs"]["missed"], 1);
  EXPECT_DOUBLE_EQ(summary["bugs"]["catch_rate"].get<double>(), 0.5);
  for (const nlohmann::json& row : summary["scenarios"]) {
    const bool caught = row["name"] == "caught";
    EXPECT_EQ(row["verdict"], caught ? "caught" : "missed") << row.dump(1);
    EXPECT_EQ(row["exit_code"], caught ? 0 : 1);
    EXPECT_EQ(row["bug"]["caught"], caught);
    EXPECT_EQ(row["bug"]["silent_checks"], caught ? nlohmann::json::array() : nlohmann::json({"finite"}));
  }

  // JUnit: the missed bug's silent check is the one failure; the caught
  // bug's failing jacobian check is not a failure.
  const std::string junit = test::read_text(out / "junit.xml");
  EXPECT_NE(junit.find("failures=\"1\""), std::string::npos) << junit;
  EXPECT_NE(junit.find("missed bug test#2: finite passed"), std::string::npos) << junit;
  EXPECT_EQ(junit.find("test#1: jacobian passed"), std::string::npos) << junit;

  const std::string report = test::read_text(out / "report.html");
  EXPECT_NE(report.find("<h2>Bug museum</h2>"), std::string::npos);
  EXPECT_NE(report.find("catch rate <b>50 %</b>"), std::string::npos);
}

TEST(BugMuseum, ABugNamingACheckTheScenarioLacksIsBadInput) {
  test::TempDir dir("bug-museum-bad");
  const auto file = dir.path() / "bad.json";
  std::ofstream(file) << broken_corners("bad", {{"source", "test#3"}, {"caught_by", {"reference"}}}).dump(1);
  const test::CommandResult r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/bug/caught_by/0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("expected the name of one of the scenario's checks"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
