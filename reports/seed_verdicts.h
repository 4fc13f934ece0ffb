// Seeds as a dimension (core/seed_set.h): a scenario run at N seeds, and
// per check the verdict at each seed and one status over them:
//   pass          every seed passed
//   flaky         some seeds passed and some did not (a failure: exit 1)
//   fail, …       no seed passed: the verdict they share, "fail" when they differ
// `run --seeds N` writes seed_set_summary() as <out>/summary.json; `nightly
// --seeds N` combines each scenario's runs into its row (apply_seed_runs) and
// the suite tallies the flaky checks (seed_tally, reports/suite_report.cpp).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

std::string seed_status(const std::vector<std::string>& verdicts);

// A row verdict that says the scenario gave no result of its checks
// (bad_input, crashed, timeout, device_error, error).
bool error_verdict(const std::string& verdict);

// "seed 1 pass, seed 2868 fail, …" (at most `limit` seeds named, then "… N more").
std::string seed_verdict_list(const std::vector<std::uint32_t>& seeds, const std::vector<std::string>& verdicts,
                              std::size_t limit = 16);

// `run --seeds N`'s combined summary. `runs[k]`: {"seed", "dir" (relative to
// the out dir), "exit_code", "checks": [{"name", "verdict", "message",
// "figures"}]}. Per check: its status, the verdict at each seed and the
// check's figures per seed (copied, not interpreted); the scenario's verdict
// (flaky when any check is, else fail when any check is not pass) and exit
// code (0 only when every check passed at every seed).
nlohmann::json seed_set_summary(const nlohmann::json& scenario, std::uint32_t base_seed, const std::vector<nlohmann::json>& runs);

// `nightly --seeds N`: `runs[k]` is the row the scenario's process wrote at
// seed k (runs[0]: the row as the run left it, before the baseline
// comparison). Adds to `row` (seed 0's, compared with its baseline):
// "seeds" (count, values, each run's verdict, exit code, summary and log,
// status, flaky_checks), each check's "seed_verdicts" and "seed_status", for
// a bug-museum row bug.seeds (caught at c of N seeds) and bug.catch_rate;
// the row's verdict becomes "flaky" when a check is flaky (for a bug: when
// it is caught at some seeds only) and its exit code takes the worst run's.
void apply_seed_runs(nlohmann::json& row, const std::vector<nlohmann::json>& runs);

// The suite's tally: {"scenarios_run_at_seeds", "flaky_scenarios",
// "flaky_checks": [{scenario, check, seeds, verdicts}]} (of a bug-museum row
// only its catching checks); null when no row was run with --seeds.
nlohmann::json seed_tally(const nlohmann::json& suite);

}  // namespace gi
