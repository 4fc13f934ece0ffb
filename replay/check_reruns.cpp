#include "replay/check_reruns.h"

#include "core/check_catalog.h"
#include "replay/capture.h"
#include "replay/run_scenario.h"

namespace gi {

void run_check_reruns(const Scenario& scenario, const RunOptions& main,
                      const std::vector<std::unique_ptr<Check>>& checks) {
  std::vector<Rerun> reruns;
  for (const auto& check : checks) {
    const std::vector<Rerun> asked = check->needs().reruns;
    reruns.insert(reruns.end(), asked.begin(), asked.end());
  }
  if (reruns.empty()) return;
  Scenario repeat = scenario;
  drop_rerunning_checks(repeat);
  repeat.capture.clear();
  RunOptions base = main;
  base.capture.clear();
  base.capture_failures = false;
  base.record_hashes = true;
  base.quiet = true;
  base.resume_from.clear();
  for (const Rerun& rerun : reruns) {
    RunOptions o = base;
    o.out_dir = main.out_dir / rerun.out_subdir;
    if (rerun.resume_from) o.resume_from = main.out_dir / capture_folder(*rerun.resume_from);
    run_scenario(repeat, o);
  }
}

}  // namespace gi
