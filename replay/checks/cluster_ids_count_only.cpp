// The device-free path of the cluster_ids check (replay/checks/cluster_ids_check.h).
#include <chrono>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "replay/checks/cluster_ids_check.h"
#include "reports/summary.h"

namespace gi {

RunResult run_cluster_ids_count_only(const Scenario& scenario, const Scene& initial, std::uint32_t frames,
                                     const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const CheckSpec* spec = scenario.find_check("cluster_ids");
  for (const CheckSpec& c : scenario.checks)
    if (c.name != "cluster_ids")
      throw InputError(scenario.file.string(), c.json_path + "/name",
                       fmt::format("no other check next to a count-only cluster_ids check (\"{}\" needs drawn "
                                   "frames); drop \"count_only\" or this check",
                                   c.name));
  const ClusterIdsCheck check(cluster_ids_params(*spec, scenario), scenario, initial, frames);

  RunResult result;
  result.checks.push_back(check.result());
  const CheckResult& c = result.checks.back();
  result.exit_code = c.passed() ? 0 : 1;
  nlohmann::json& s = result.summary;
  s["schema_version"] = 1;
  s["scenario"] = {{"name", scenario.name}, {"file", scenario.file.string()}, {"document", scenario.raw}};
  s["resolved"] = {{"frames", frames}, {"mode", "count_only"}};
  s["scene"] = {{"name", initial.name}, {"instances", initial.instances.size()}, {"triangles", initial.triangle_count()}};
  s["build"] = build_info();
  s["verdict"] = c.passed() ? "pass" : "fail";
  s["exit_code"] = result.exit_code;
  s["checks"] = nlohmann::json::array({c.to_json()});
  s["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_json_file(options.out_dir / "summary.json", s);
  spdlog::log(c.passed() ? spdlog::level::info : spdlog::level::err, "{}: check cluster_ids {}: {}", scenario.name,
              to_string(c.verdict), c.message);
  return result;
}

}  // namespace gi
