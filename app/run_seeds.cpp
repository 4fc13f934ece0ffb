// `giharness run SCENARIO --seeds N`: the scenario at each seed of its seed
// set (core/seed_set.h; seed 0 is --seed, else the scenario's own, so
// `--seeds 1` runs exactly what `run` runs), one after the other in this
// process, each into <out>/seed-<value>/ with its own summary.json; then
// <out>/summary.json combines them (reports/seed_verdicts.h): per check the
// verdict at each seed, its figures per seed and pass / fail / flaky.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/seed_set.h"
#include "app/commands.h"
#include "reports/seed_verdicts.h"

namespace gi {

int run_seed_set(const Scenario& scenario, const RunOptions& options, std::uint32_t count) {
  const std::uint32_t base = options.seed.value_or(scenario.seed);
  const std::vector<std::uint32_t> seeds = seed_set(base, count);
  std::vector<nlohmann::json> runs;
  for (std::size_t k = 0; k < seeds.size(); ++k) {
    RunOptions ro = options;
    // Seed 0 is the run `run` makes without --seeds (options.seed as given).
    if (k > 0) ro.seed = seeds[k];
    const std::string dir = seed_dir_name(seeds[k]);
    ro.out_dir = options.out_dir / dir;
    if (!options.quiet) spdlog::info("seed {} of {}: {} into {}", k + 1, seeds.size(), seeds[k], ro.out_dir.string());
    const RunResult r = run_scenario(scenario, ro);
    nlohmann::json run = {{"seed", seeds[k]}, {"dir", dir}, {"exit_code", r.exit_code}, {"checks", nlohmann::json::array()}};
    for (const CheckResult& c : r.checks)
      run["checks"].push_back(
          {{"name", c.name}, {"verdict", to_string(c.verdict)}, {"message", c.message}, {"figures", c.figures}});
    runs.push_back(std::move(run));
  }
  nlohmann::json summary = seed_set_summary({{"name", scenario.name}, {"file", scenario.file.string()}}, base, runs);
  summary["seed_rule"] = seed_rule_text();
  std::filesystem::create_directories(options.out_dir);
  write_json_file(options.out_dir / "summary.json", summary);
  for (const nlohmann::json& c : summary["checks"]) {
    const std::string status = c["status"];
    spdlog::log(status == "pass" ? spdlog::level::info : spdlog::level::err, "{}: check {} {} (pass at {} of {} seeds: {})",
                scenario.name, c["name"].get<std::string>(), status, c["passed_at"].get<std::size_t>(),
                c["seeds"].get<std::size_t>(), seed_verdict_list(seeds, c["verdicts"].get<std::vector<std::string>>()));
  }
  spdlog::info("{}: {} at {} seeds from {}; {}", scenario.name, summary["verdict"].get<std::string>(), seeds.size(), base,
               (options.out_dir / "summary.json").string());
  return summary["exit_code"].get<int>();
}

}  // namespace gi
