// run_scenario in three parts: the setup (replay/run_setup.h: profile, scene,
// checks, renderer options; no device), the frames (replay/frame_loop.h) and
// the summary (replay/run_summary.h). The checks are found by name in their
// registry (checks/check_registry.h); nothing here names one.
#include "replay/run_scenario.h"

#include <algorithm>
#include <chrono>

#include <spdlog/spdlog.h>

#include "core/phase_clock.h"
#include "gpu/device.h"
#include "replay/check_reruns.h"
#include "replay/device_free_run.h"
#include "replay/failure_capture.h"
#include "replay/frame_loop.h"
#include "replay/rc_run.h"
#include "replay/resource_limits.h"
#include "replay/run_setup.h"
#include "core/reference/reference_cache.h"
#include "replay/run_summary.h"

namespace gi {

RunResult run_scenario(const Scenario& scenario, const RunOptions& options) {
  // The seed lesson's 2D radiance cascades: a pipeline of its own.
  if (scenario.pipeline == Pipeline::RadianceCascades) return run_rc_scenario(scenario, options);
  const auto started = std::chrono::steady_clock::now();
  const std::map<std::string, double> phases_at_start = phase_seconds();
  const std::size_t references_at_start = reference_entries_used().size();
  RunSetup setup = [&] {
    const PhaseScope timed(phase::kScene);
    return RunSetup(scenario, options);
  }();
  // A check that decides without drawing (cluster_ids "count_only", a lone
  // furnace check): no device, its result is the run's.
  for (auto& check : setup.checks)
    if (const std::optional<std::string> mode = check->decides_alone())
      return finish_device_free_run(scenario, setup.initial, setup.frames, options, check->result(), *mode, started);

  check_resource_limits(scenario, setup.initial, 0);
  gpu::Device device(options.device, gpu::parse_backend_request(options.backend));
  check_resource_limits(scenario, setup.initial, device.largest_heap_bytes(), device.limits().maxStorageBufferRange);
  FrameLoop loop(scenario, options, setup, device);
  loop.run();

  run_check_reruns(scenario, options, setup.checks);
  RunResult result;
  for (auto& check : setup.checks) result.checks.push_back(check->result());
  const bool all_pass =
      std::all_of(result.checks.begin(), result.checks.end(), [](const CheckResult& c) { return c.passed(); });
  result.exit_code = all_pass ? 0 : 1;
  // Nightly: the first failing frame of each failing check, captured by a
  // second, bit-identical run; before the summary, as it adds the captures
  // to the checks' evidence.
  nlohmann::json failure_captures = nlohmann::json::array();
  if (options.capture_failures && !all_pass && options.resume_from.empty())
    failure_captures = capture_failing_frames(scenario, options, setup.frames, loop.captured_frames(), result.checks);
  write_run_summary({scenario, options, setup, loop, device, started, phases_at_start, references_at_start}, failure_captures, result);

  for (const CheckResult& c : result.checks)
    spdlog::log(c.passed() ? spdlog::level::info : spdlog::level::err, "{}: check {} {}: {}", scenario.name, c.name,
                to_string(c.verdict), c.message);
  return result;
}

}  // namespace gi
