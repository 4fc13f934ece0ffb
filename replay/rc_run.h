// A scenario of "pipeline": "radiance_cascades" end to end: the
// canvas at each frame under the events, the RC passes on the device, the
// frame record (image hash, per-pass ms), the rc_* checks on the frames they
// judge (each given the output and, computed once per canvas and shared, the
// 2D path tracer's reference), captures of every intermediate (scene,
// distance field, each cascade, mipmap), and summary.json in the shape
// run_scenario writes, so the nightly, baselines and reports read it alike.
//
// Nothing carries from frame to frame: a frame is a pure function of the
// scenario and its index, so a run from frame f (--frames, a replay) gives
// the same bits as the full run's frame f.
#pragma once
#include "core/scenario.h"
#include "replay/run_scenario.h"

namespace gi {

// InputError (exit 2) for what the run cannot honour, DeviceError (exit 3).
RunResult run_rc_scenario(const Scenario& scenario, const RunOptions& options);

}  // namespace gi
