// `giharness sweep` on a radiance-cascades scenario: speed
// against error for the lesson's pipeline, with the 2D path tracer at equal
// time beside each point (app/rc_sweep.cpp).
#pragma once
#include <vector>

#include "core/scenario.h"
#include "app/commands.h"
#include "app/sweep_plan.h"

namespace gi {

int run_rc_sweep(const SweepOptions& options, const Scenario& base, const std::vector<SweepPoint>& points,
                 const std::vector<Scenario>& scenarios);

}  // namespace gi
