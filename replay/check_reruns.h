// The reruns checks ask for (CheckNeeds::reruns: the determinism check's
// second run and replay), carried out by the run engine after the main run's
// last frame and before any check's result(). A check names what it wants
// compared; only the run engine starts a run.
#pragma once
#include <memory>
#include <vector>

#include "checks/check.h"
#include "core/run_options.h"
#include "core/scenario.h"

namespace gi {

// Each rerun goes into <main.out_dir>/<rerun.out_subdir> with its hashes
// recorded; a resumed one continues from the main run's capture of its frame.
// The reruns run the same pipeline (every other check is kept: checks choose
// passes and chains) without the checks that rerun, the scenario's captures or
// failure captures.
void run_check_reruns(const Scenario& scenario, const RunOptions& main,
                      const std::vector<std::unique_ptr<Check>>& checks);

}  // namespace gi
