// The device-free path of the cluster_ids check (checks/cluster_ids_check.h).
#include <fmt/format.h>

#include "checks/cluster_ids_check.h"
#include "core/errors.h"

namespace gi {

void refuse_checks_beside_count_only(const Scenario& scenario) {
  for (const CheckSpec& c : scenario.checks)
    if (c.name != "cluster_ids")
      throw InputError(scenario.file.string(), c.json_path + "/name",
                       fmt::format("no other check next to a count-only cluster_ids check (\"{}\" needs drawn "
                                   "frames); drop \"count_only\" or this check",
                                   c.name));
}

CheckResult count_only_result(const ClusterIdsParams& params, const Scenario& scenario, const Scene& initial,
                              std::uint32_t frames) {
  return ClusterIdsCheck(params, scenario, initial, frames).result();
}

}  // namespace gi
