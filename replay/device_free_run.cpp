#include "replay/device_free_run.h"

#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "reports/summary.h"

namespace gi {

RunResult finish_device_free_run(const Scenario& scenario, const Scene& initial, std::uint32_t frames,
                                 const RunOptions& options, const CheckResult& c, const std::string& mode,
                                 std::chrono::steady_clock::time_point started) {
  RunResult result;
  result.checks.push_back(c);
  result.exit_code = c.passed() ? 0 : 1;
  nlohmann::json& s = result.summary;
  s["schema_version"] = 1;
  s["scenario"] = {{"name", scenario.name}, {"file", scenario.file.string()}, {"document", scenario.raw}};
  s["resolved"] = {{"frames", frames}, {"mode", mode}};
  s["scene"] = {{"name", initial.name}, {"instances", initial.instances.size()}, {"triangles", initial.triangle_count()}};
  s["build"] = build_info();
  s["verdict"] = c.passed() ? "pass" : "fail";
  s["exit_code"] = result.exit_code;
  s["checks"] = nlohmann::json::array({c.to_json()});
  s["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  write_json_file(options.out_dir / "summary.json", s);
  spdlog::log(c.passed() ? spdlog::level::info : spdlog::level::err, "{}: check {} {}: {}", scenario.name, c.name,
              to_string(c.verdict), c.message);
  return result;
}

}  // namespace gi
