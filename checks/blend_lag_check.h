// The blend_lag check (docs/design.md §6): how fast the world cache follows a lighting
// change, and how still it holds when nothing changes, judged on signals Bevy
// computes: the mean luminance of the output (DI + GI + specular) and of GI,
// and the mean irradiance of the cells sampled this frame (those GI's queries
// keep alive). The cache view's mean luminance (irradiance at every primary
// surface) is a debug signal: it needs the view ("cache_view": true), whose
// queries Bevy makes only under VISUALIZE_WORLD_CACHE and which keep cells
// alive that GI alone would let die.
//
// The scenario's lighting events (light_on/off/intensity/colour) cut the run
// into windows. In each window after an event, the new steady state is the
// mean of the window's last `steady_frames`; the lag is the frames from the
// event until the signal stays within ε · max(|old|, |new|) of it (old: the
// mean of the `steady_frames` before the event). Passes when every lag ≤
// `lag_limit` and, in every window from `lag_limit` frames after its start
// on, |s(t) − s(t − 1)| ≤ δ · that window's level. The response is the
// frames from the event until the signal first leaves the old level's band
// (the same ε); with `response_limit` set, a later response fails: a
// one-frame delay is far below what the lag resolves.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "checks/check_result.h"

namespace gi {

struct BlendLagParams {
  double epsilon = 0.05;            // settling band, relative to the larger of the two levels
  double delta = 0.02;              // frame-to-frame variation in static windows, relative to the level
  std::uint32_t lag_limit = 10;     // frames
  std::uint32_t steady_frames = 8;  // frames averaged for a steady state
  // Largest delay from an event to the first frame outside the old level's
  // band (none: recorded, not judged). 0 asks the event's own frame to show
  // it, as Solari's pass order does since #21348.
  std::optional<std::uint32_t> response_limit;
  // The signals judged (every available one is recorded per frame either way).
  std::vector<std::string> signals = {"output_luminance"};
};

inline const std::vector<std::string> kBlendLagSignals = {"output_luminance", "gi_luminance", "cache_mean_radiance",
                                                          "cache_view_luminance"};

// Defaults, then the check's params; InputError naming the JSON path.
BlendLagParams blend_lag_params(const CheckSpec& spec, const Scenario& scenario);

// Frames at which a lighting event starts (sorted, unique).
std::vector<std::uint32_t> lighting_event_frames(const Scenario& scenario);

struct BlendLagSignal {
  std::string name;            // one of kBlendLagSignals
  std::vector<double> values;  // one per frame from 0
};

// The verdict over whole runs of both signals (pure: the tests feed it curves).
CheckResult judge_blend_lag(const BlendLagParams& params, const std::vector<std::uint32_t>& event_frames,
                            const std::vector<BlendLagSignal>& signals);

}  // namespace gi
