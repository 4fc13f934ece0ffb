// Seeds as a dimension (core/seed_set.h, reports/seed_verdicts.h): the rule
// that derives a scenario's seeds, the status of a check over them, and
// `run --seeds N` / `nightly --seeds N` end to end on the radiance-cascades
// pipeline (a second a run: its 2D reference is path traced from the seed,
// so a check's figures move with it while the output stays put).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "core/seed_set.h"
#include "reports/junit.h"
#include "reports/seed_verdicts.h"
#include "tests/test_support.h"

namespace gi {
namespace {

TEST(SeedSet, TheRuleGivesTheseSeeds) {
  // splitmix64 itself: SplittableRandom(0)'s first value.
  EXPECT_EQ(splitmix64(0), 0xE220A8397B1DCDAFull);
  // Seed 0 is the base; the others are the rule's (a change of the rule
  // changes every night's seeds: it must be noticed here).
  EXPECT_EQ(seed_set(1, 4), (std::vector<std::uint32_t>{1u, 3596284446u, 2524120683u, 840412675u}));
  EXPECT_EQ(seed_set(0, 3), (std::vector<std::uint32_t>{0u, 3365057806u, 4284480057u}));
  EXPECT_EQ(seed_set(0xFFFFFFFFu, 3), (std::vector<std::uint32_t>{0xFFFFFFFFu, 2362659753u, 704781639u}));
  EXPECT_EQ(seed_set(42, 1), std::vector<std::uint32_t>{42u});
  EXPECT_TRUE(seed_set(42, 0).empty());
  EXPECT_EQ(seed_dir_name(3596284446u), "seed-3596284446");
}

TEST(SeedSet, SeedsAreDistinctAndAPrefixOfALargerSet) {
  for (std::uint32_t base : {0u, 1u, 7u, 123456789u, 0xFFFFFFFFu}) {
    const std::vector<std::uint32_t> all = seed_set(base, kMaxSeeds);
    ASSERT_EQ(all.size(), kMaxSeeds);
    EXPECT_EQ(all[0], base);
    EXPECT_EQ(std::set<std::uint32_t>(all.begin(), all.end()).size(), all.size()) << "base " << base;
    const std::vector<std::uint32_t> few = seed_set(base, 10);
    EXPECT_TRUE(std::equal(few.begin(), few.end(), all.begin())) << "base " << base;
  }
  // Neighbouring bases do not share their derived seeds.
  const std::vector<std::uint32_t> a = seed_set(1, 100), b = seed_set(2, 100);
  std::set<std::uint32_t> sa(a.begin() + 1, a.end());
  EXPECT_EQ(std::count_if(b.begin() + 1, b.end(), [&](std::uint32_t s) { return sa.count(s) > 0; }), 0);
}

TEST(SeedVerdicts, StatusOverSeeds) {
  EXPECT_EQ(seed_status({"pass", "pass", "pass"}), "pass");
  EXPECT_EQ(seed_status({"pass", "fail", "pass"}), "flaky");
  EXPECT_EQ(seed_status({"fail", "pass"}), "flaky");
  EXPECT_EQ(seed_status({"pass", "crashed"}), "flaky");
  EXPECT_EQ(seed_status({"fail", "fail"}), "fail");
  EXPECT_EQ(seed_status({"inconclusive", "inconclusive"}), "inconclusive");
  EXPECT_EQ(seed_status({"fail", "inconclusive"}), "fail");  // no seed passed: not flaky
  EXPECT_EQ(seed_status({"pass"}), "pass");
  EXPECT_EQ(seed_verdict_list({1, 2, 3}, {"pass", "fail", "pass"}, 2), "seed 1 pass, seed 2 fail, … 1 more");
}

nlohmann::json run_row(std::uint32_t seed, const std::string& verdict, const std::vector<std::string>& checks) {
  nlohmann::json row = {{"seed", seed}, {"verdict", verdict}, {"exit_code", verdict == "pass" || verdict == "caught" ? 0 : 1},
                        {"checks", nlohmann::json::array()}};
  for (std::size_t i = 0; i < checks.size(); ++i)
    row["checks"].push_back({{"name", "c" + std::to_string(i)}, {"verdict", checks[i]}, {"message", "m"}});
  return row;
}

TEST(SeedVerdicts, AFlakyCheckMakesTheRowFlakyAndFailsItsJUnitCase) {
  std::vector<nlohmann::json> runs = {run_row(1, "pass", {"pass", "pass"}), run_row(9, "fail", {"pass", "fail"}),
                                      run_row(5, "pass", {"pass", "pass"})};
  nlohmann::json row = runs[0];
  row["name"] = "s";
  row["status"] = "complete";
  apply_seed_runs(row, runs);
  EXPECT_EQ(row["verdict"], "flaky");
  EXPECT_EQ(row["exit_code"], 1);
  EXPECT_EQ(row["checks"][0]["seed_status"], "pass");
  EXPECT_EQ(row["checks"][1]["seed_status"], "flaky");
  EXPECT_EQ(row["checks"][1]["seed_verdicts"], (nlohmann::json{"pass", "fail", "pass"}));
  EXPECT_EQ(row["seeds"]["values"], (nlohmann::json{1, 9, 5}));
  EXPECT_EQ(row["seeds"]["flaky_checks"], (nlohmann::json{"c1"}));
  const nlohmann::json suite = {{"suite", "t"}, {"scenarios", {row}}};
  const nlohmann::json tally = seed_tally(suite);
  ASSERT_EQ(tally["flaky_checks"].size(), 1u);
  EXPECT_EQ(tally["flaky_checks"][0]["check"], "c1");
  const std::string junit = junit_xml(suite);
  EXPECT_NE(junit.find("flaky: passed at 2 of 3 seeds: seed 1 pass, seed 9 fail, seed 5 pass"), std::string::npos) << junit;
  EXPECT_NE(junit.find("failures=\"1\""), std::string::npos) << junit;

  // Every seed passing leaves the row as it was; no seed ran a check: null tally.
  std::vector<nlohmann::json> clean = {run_row(1, "pass", {"pass"}), run_row(2, "pass", {"pass"})};
  nlohmann::json ok = clean[0];
  apply_seed_runs(ok, clean);
  EXPECT_EQ(ok["verdict"], "pass");
  EXPECT_EQ(ok["exit_code"], 0);
  EXPECT_TRUE(seed_tally(nlohmann::json{{"scenarios", {clean[0]}}}).is_null());
}

TEST(SeedVerdicts, ABugCaughtAtSomeSeedsIsFlakyWithItsCatchRate) {
  const nlohmann::json bug = {{"source", "x#1"}, {"caught_by", {"c0"}}, {"caught", true}};
  std::vector<nlohmann::json> runs = {run_row(1, "caught", {"fail"}), run_row(2, "missed", {"pass"}),
                                      run_row(3, "caught", {"fail"})};
  nlohmann::json row = runs[0];
  row["bug"] = bug;
  apply_seed_runs(row, runs);
  EXPECT_EQ(row["verdict"], "flaky");
  EXPECT_EQ(row["exit_code"], 1);
  EXPECT_EQ(row["bug"]["seeds"]["text"], "caught at 2 of 3 seeds");
  EXPECT_DOUBLE_EQ(row["bug"]["catch_rate"].get<double>(), 2.0 / 3.0);
  EXPECT_FALSE(row["bug"]["caught"].get<bool>());
  const std::string junit = junit_xml({{"scenarios", {row}}});
  EXPECT_NE(junit.find("missed bug x#1 at 1 of 3 seeds"), std::string::npos) << junit;
}

TEST(SeedsCli, BadSeedCountsAreBadInput) {
  const std::string scenario = (test::source_dir() / "scenarios/rc_wall_leak.json").string();
  for (const char* n : {"0", "1001", "-1", "x"}) {
    const auto r = test::run_giharness("run " + scenario + " --seeds " + n + " --out /nonexistent/never");
    EXPECT_EQ(r.exit_code, 2) << n << ": " << r.output;
    EXPECT_NE(r.output.find("--seeds"), std::string::npos) << r.output;
    const auto nightly = test::run_giharness("nightly --suite /nonexistent --seeds " + std::string(n));
    EXPECT_EQ(nightly.exit_code, 2) << n << ": " << nightly.output;
  }
}

TEST(SeedsCli, RunSeedsOneIsTheRunWithoutSeeds) {
  const test::TempDir dir("seeds-one");
  const std::string scenario = (test::source_dir() / "scenarios/rc_wall_leak.json").string();
  const auto plain = test::run_giharness("run " + scenario + " --out " + (dir.path() / "plain").string());
  const auto one = test::run_giharness("run " + scenario + " --seeds 1 --out " + (dir.path() / "one").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const nlohmann::json a = test::read_json(dir.path() / "plain/summary.json");
  const nlohmann::json b = test::read_json(dir.path() / "one/seed-1/summary.json");  // rc_wall_leak's seed: the default 1
  for (const char* key : {"checks", "hashes", "resolved", "final_image_hash"}) EXPECT_EQ(a[key], b[key]) << key;
  const nlohmann::json combined = test::read_json(dir.path() / "one/summary.json");
  EXPECT_EQ(combined["seeds"], (nlohmann::json{1}));
  EXPECT_EQ(combined["verdict"], "pass");
  EXPECT_EQ(combined["checks"][0]["per_seed"][0]["figures"], a["checks"][0]["figures"]);
}

// rc_grating_penumbra's rc_energy at the first three seeds of its set: the
// energy ratio against the 2D path tracer moves with the seed (its noise),
// by about 1e-5. A max_gain between the seeds' figures makes the check pass
// at some and fail at others. Returns that max_gain and the verdict it gives
// at each seed (as the check decides: ratio > 1 + max_gain + 3 sigma fails).
struct FlakyGain {
  double max_gain = 0;
  std::vector<std::string> verdicts;
};

FlakyGain measure_flaky_gain(const std::filesystem::path& dir) {
  const std::string scenario = (test::source_dir() / "scenarios/rc_grating_penumbra.json").string();
  const auto r = test::run_giharness("run " + scenario + " --seeds 3 --out " + (dir / "measure").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json s = test::read_json(dir / "measure/summary.json");
  std::vector<double> excess;  // ratio - 3 sigma - 1 at each seed
  for (const nlohmann::json& c : s["checks"])
    if (c["name"] == "rc_energy")
      for (const nlohmann::json& p : c["per_seed"])
        excess.push_back(p["figures"]["energy_ratio"].get<double>() - 3 * p["figures"]["sigma"].get<double>() - 1);
  EXPECT_EQ(excess.size(), 3u) << s.dump(1);
  FlakyGain g;
  if (excess.size() != 3) return g;
  const auto [lo, hi] = std::minmax_element(excess.begin(), excess.end());
  EXPECT_GT(*hi - *lo, 1e-7) << "the seeds' energy ratios should differ";
  g.max_gain = double(float((*lo + *hi) / 2));  // the check keeps it as a float
  for (double e : excess) g.verdicts.push_back(e > g.max_gain ? "fail" : "pass");
  return g;
}

void write_flaky_variant(const std::filesystem::path& file, const std::string& name, double max_gain, bool bug) {
  std::filesystem::create_directories(file.parent_path());
  test::write_scenario_variant("scenarios/rc_grating_penumbra.json", file.parent_path(), file.filename().string(),
                               [&](nlohmann::json& doc) {
                                 doc["name"] = name;
                                 for (nlohmann::json& c : doc["checks"])
                                   if (c["name"] == "rc_energy") c["max_gain"] = max_gain;
                                 if (bug)
                                   doc["bug"] = {{"source", "test#1"}, {"symptom", "too much energy"},
                                                 {"caught_by", {"rc_energy"}}};
                               });
}

TEST(SeedsCli, RunSeedsShowsACheckFlakyWithItsFiguresPerSeed) {
  const test::TempDir dir("seeds-run");
  const FlakyGain g = measure_flaky_gain(dir.path());
  ASSERT_EQ(g.verdicts.size(), 3u);
  ASSERT_EQ(seed_status(g.verdicts), "flaky") << "the midpoint splits the seeds";
  const std::filesystem::path file = dir.path() / "variant/flaky.json";
  write_flaky_variant(file, "flaky_energy", g.max_gain, false);
  const std::filesystem::path out = dir.path() / "out";
  const auto r = test::run_giharness("run " + file.string() + " --seeds 3 --out " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("check rc_energy flaky"), std::string::npos) << r.output;
  const nlohmann::json s = test::read_json(out / "summary.json");
  EXPECT_EQ(s["verdict"], "flaky");
  EXPECT_EQ(s["exit_code"], 1);
  EXPECT_EQ(s["base_seed"], 1);
  EXPECT_EQ(s["seeds"], (nlohmann::json{1u, 3596284446u, 2524120683u}));
  for (const nlohmann::json& c : s["checks"]) {
    if (c["name"] == "rc_penumbra") {
      EXPECT_EQ(c["status"], "pass");
    }
    if (c["name"] != "rc_energy") continue;
    EXPECT_EQ(c["status"], "flaky");
    EXPECT_EQ(c["verdicts"], nlohmann::json(g.verdicts));
    ASSERT_EQ(c["per_seed"].size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string seed_dir = seed_dir_name(s["seeds"][k].get<std::uint32_t>());
      const nlohmann::json own = test::check_result(out / seed_dir, "rc_energy");
      EXPECT_EQ(c["per_seed"][k]["figures"], own["figures"]) << "copied from " << seed_dir;
      EXPECT_EQ(c["per_seed"][k]["verdict"], own["verdict"]);
    }
  }
  // --seed moves the base: its set starts there.
  const auto from = test::run_giharness("run " + file.string() + " --seed 0 --seeds 2 --out " + (dir.path() / "from0").string());
  EXPECT_EQ(test::read_json(dir.path() / "from0/summary.json")["seeds"], (nlohmann::json{0u, 3365057806u})) << from.output;
}

TEST(SeedsCli, NightlySeedsReportsFlakyChecksAndTheBugsCatchRate) {
  const test::TempDir dir("seeds-nightly");
  const FlakyGain g = measure_flaky_gain(dir.path());
  ASSERT_EQ(seed_status(g.verdicts), "flaky");
  const std::filesystem::path suite = dir.path() / "suite", out = dir.path() / "out";
  write_flaky_variant(suite / "1_flaky.json", "flaky_energy", g.max_gain, false);
  write_flaky_variant(suite / "2_bug.json", "bug_energy", g.max_gain, true);
  const auto r = test::run_giharness("nightly --suite " + suite.string() + " --out " + out.string() + " --baseline " +
                                     (dir.path() / "none").string() + " --seeds 3");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const nlohmann::json s = test::read_json(out / "summary.json");
  EXPECT_EQ(s["verdict"], "fail");
  EXPECT_EQ(s["seeds"]["count"], 3);
  EXPECT_EQ(s["seeds"]["flaky_checks"].size(), 2u) << s["seeds"].dump(1);
  const std::vector<std::uint32_t> seeds = seed_set(1, 3);
  const std::size_t caught = std::count(g.verdicts.begin(), g.verdicts.end(), std::string("fail"));
  for (const nlohmann::json& row : s["scenarios"]) {
    EXPECT_EQ(row["verdict"], "flaky") << row.dump(1);
    EXPECT_EQ(row["exit_code"], 1);
    // Seed 0 keeps today's layout (baselines, reports); the others a folder each inside it.
    const std::string name = row["name"];
    EXPECT_EQ(row["summary"], name + "/summary.json");
    EXPECT_TRUE(std::filesystem::exists(out / name / "run.log"));
    for (std::size_t k = 1; k < seeds.size(); ++k) {
      EXPECT_TRUE(std::filesystem::exists(out / name / seed_dir_name(seeds[k]) / "summary.json")) << k;
      EXPECT_TRUE(std::filesystem::exists(out / name / seed_dir_name(seeds[k]) / "run.log")) << k;
    }
    EXPECT_EQ(row["seeds"]["values"], nlohmann::json(seeds));
    for (const nlohmann::json& c : row["checks"])
      if (c["name"] == "rc_energy") {
        EXPECT_EQ(c["seed_verdicts"], nlohmann::json(g.verdicts));
        EXPECT_EQ(c["seed_status"], "flaky");
      }
    if (name == "bug_energy") {
      EXPECT_EQ(row["bug"]["seeds"]["text"], "caught at " + std::to_string(caught) + " of 3 seeds") << row["bug"].dump(1);
    }
  }
  EXPECT_EQ(s["bugs"]["flaky"], 1);
  EXPECT_EQ(s["bugs"]["seed_runs_caught"], caught);
  const std::string junit = test::read_text(out / "junit.xml");
  EXPECT_NE(junit.find("flaky: passed at " + std::to_string(3 - caught) + " of 3 seeds: seed 1 " + g.verdicts[0]),
            std::string::npos)
      << junit;
  EXPECT_NE(junit.find("missed bug test#1 at " + std::to_string(3 - caught) + " of 3 seeds"), std::string::npos) << junit;
  const std::string html = test::read_text(out / "report.html");
  EXPECT_NE(html.find("<h2>Seeds</h2>"), std::string::npos);
  EXPECT_NE(html.find("verdict flaky"), std::string::npos);
  EXPECT_NE(html.find("caught at " + std::to_string(caught) + " of 3 seeds"), std::string::npos);

  // --resume with the same seeds keeps the night; with another count it runs again.
  const auto again = test::run_giharness("nightly --suite " + suite.string() + " --out " + out.string() + " --baseline " +
                                         (dir.path() / "none").string() + " --seeds 3 --resume");
  EXPECT_NE(again.output.find("2 of 2 scenarios already complete"), std::string::npos) << again.output;
}

TEST(SeedsCli, SlurmShardsRunAtTheSeedsToo) {
  const test::TempDir dir("seeds-slurm");
  const auto r = test::run_giharness("nightly --suite " + (test::source_dir() / "tests/data/suites/tiny").string() +
                                     " --out " + (dir.path() / "out").string() + " --slurm 2 --slurm-dry-run --seeds 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string array = test::read_text(dir.path() / "out/slurm/nightly-array.sh");
  const std::size_t at = array.find("--seeds");
  ASSERT_NE(at, std::string::npos) << array;
  EXPECT_NE(array.substr(at, 16).find('3'), std::string::npos) << array.substr(at, 16);
}

}  // namespace
}  // namespace gi
