// Speed against error as the ReSTIR papers measure it: the
// realtime output beside unbiased path tracers given the same time per frame,
// and the time each needs to reach the realtime output's error.
//
// The peers, both rendering the scene of the judged frame at the run's
// resolution, the same quantity the realtime output estimates (DI alone, or
// the full image with "gi": true):
//   - the GPU path tracer (gpu/shaders/reference_path_trace.comp) on the
//     realtime run's own device: the equal-time peer of the same machine;
//   - the Embree path tracer on the CPU, as `sweep` always had it.
// Each peer's cost is measured, not assumed: renders at 1 and 16 spp split
// it into a per-render and a per-sample part (the fastest of 3 repeats: a
// shared machine only ever slows a render). The budget is the realtime
// pipeline's ms/frame (the sum of its passes' median GPU times, observation
// passes left out); the peer renders the spp that fits it, on sample indices
// from reference_spp on, which the converged reference never used.
//
// Equal-error time. A path tracer's relMSE against the reference falls as
// v1 / n + r with n spp: v1 is its relMSE per sample, measured from its own
// two halves, and r the reference's own noise, which any estimate compared
// with it carries. An error E > r costs fixed + per_spp × v1 / (E − r). The
// ratio of that time to the realtime pipeline's time for the same error
// (one frame for the per-frame error, the window's frames for the temporal
// mean's) is the papers' figure: above 1, the realtime estimator is faster.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/reference/embree_reference.h"
#include "core/scene.h"

namespace gi {

namespace gpu {
class Device;
class ShaderCompiler;
}  // namespace gpu

// A renderer's cost: milliseconds = fixed_ms + spp × per_spp_ms.
struct RenderCost {
  double fixed_ms = 0, per_spp_ms = 0;
  // The spp that fit `budget_ms` (at least 1, at most 65536).
  std::uint32_t spp_within(double budget_ms) const;
};

// The cost from the fastest of `repeats` renders at 1 and 16 spp each
// (`render(spp)` returns milliseconds). Timer noise that makes the per-sample
// part non-positive puts it all on the samples.
RenderCost measure_cost(const std::function<double(std::uint32_t)>& render, int repeats = 3);

// The time to reach relMSE `error` for an unbiased estimator of per-sample
// relMSE v1 against a reference of noise r (see above); nullopt at or
// below r, which no estimate compared with this reference can show.
std::optional<double> equal_error_ms(const RenderCost& cost, double v1, double reference_noise, double error);

// What the realtime run measured.
struct RealtimePoint {
  double ms_per_frame = 0;        // the pipeline's passes, median GPU ms
  double frame_relmse = 0;        // one chain's frame against the reference
  double temporal_relmse = 0;     // the temporal mean of the window against it
  std::uint32_t window_frames = 0;
};

struct EqualTimeTarget {
  const Scene* scene = nullptr;          // the scene of the judged frame (events applied)
  ReferenceOptions reference_options;    // the converged reference's (width, height, seed, direct_only, spp)
  const ReferenceResult* reference = nullptr;
  RealtimePoint realtime;
  bool embree = true;                    // also the Embree peer
  // Embree's cost when already measured for this scene state and resolution
  // (a sweep's points share it; `out` of equal_time_figures' "embree"
  // "cost"): not measured again.
  std::optional<RenderCost> embree_cost;
};

// {"method", "reference", "realtime", "gpu_path_tracer", "embree"}: each
// peer's spp, sample indices, ms, relMSE, its noise and per-sample relMSE,
// its cost, and the equal-error times and ratios. `device` null: no GPU peer.
nlohmann::json equal_time_figures(gpu::Device* device, gpu::ShaderCompiler* compiler, const EqualTimeTarget& target);

}  // namespace gi
