// The device-free path of the cluster_ids check (replay/checks/cluster_ids_check.h).
#include <chrono>

#include <fmt/format.h>

#include "core/errors.h"
#include "replay/checks/cluster_ids_check.h"
#include "replay/device_free_run.h"

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
  return finish_device_free_run(scenario, initial, frames, options, check.result(), "count_only", start);
}

}  // namespace gi
