// `giharness sweep` on a radiance-cascades scenario (issue 18): speed
// against error for the lesson's pipeline, with the 2D path tracer at equal
// time beside each point (replay/cli/rc_sweep.cpp).
#pragma once
#include <vector>

#include "core/scenario.h"
#include "replay/cli/commands.h"
#include "replay/cli/sweep_plan.h"

namespace gi {

int run_rc_sweep(const SweepOptions& options, const Scenario& base, const std::vector<SweepPoint>& points,
                 const std::vector<Scenario>& scenarios);

}  // namespace gi
