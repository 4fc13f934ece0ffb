// `giharness nightly`: every scenario of a suite, one summary per scenario and
// one for the suite. Baselines, HTML, JUnit and sharding come later (DESIGN §10).
#include <algorithm>
#include <chrono>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/scenario.h"
#include "gpu/device.h"
#include "replay/commands.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {

int run_nightly(const NightlyOptions& o) {
  if (!std::filesystem::is_directory(o.suite))
    throw InputError(o.suite.string(), "", "expected a directory of scenario files");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(o.suite))
    if (entry.is_regular_file() && entry.path().extension() == ".json" && entry.path().filename() != "schema.json")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(o.suite.string(), "", "expected at least one *.json scenario");

  const auto start = std::chrono::steady_clock::now();
  nlohmann::json suite;
  suite["schema_version"] = 1;
  suite["suite"] = o.suite.string();
  suite["build"] = build_info();
  suite["scenarios"] = nlohmann::json::array();
  int worst = 0;
  std::size_t index = 0;
  for (const std::filesystem::path& file : files) {
    ++index;
    nlohmann::json row = {{"file", file.string()}};
    const auto t0 = std::chrono::steady_clock::now();
    int code = 0;
    try {
      const Scenario scenario = load_scenario(file);
      row["name"] = scenario.name;
      spdlog::info("[{}/{}] {}", index, files.size(), scenario.name);
      RunOptions ro;
      ro.device = o.device;
      ro.out_dir = o.out_dir / scenario.name;
      const RunResult r = run_scenario(scenario, ro);
      code = r.exit_code;
      row["summary"] = (std::filesystem::path(scenario.name) / "summary.json").string();
      row["checks"] = nlohmann::json::array();
      for (const CheckResult& c : r.checks)
        row["checks"].push_back({{"name", c.name}, {"verdict", to_string(c.verdict)}, {"message", c.message}});
      if (!suite.contains("device")) suite["device"] = r.summary["device"];
    } catch (const InputError& e) {
      code = 2;
      row["error"] = e.what();
      spdlog::error("{}", e.what());
    } catch (const DeviceError& e) {
      code = 3;
      row["error"] = e.what();
      spdlog::error("{}", e.what());
    }
    row["exit_code"] = code;
    row["verdict"] = code == 0 ? "pass" : code == 1 ? "fail" : "error";
    row["wall_seconds"] = json_figure(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    suite["scenarios"].push_back(row);
    // Severity order: a device error outranks bad input, which outranks a failed check.
    worst = std::max(worst, code);
    // Rewritten after every scenario, so an interrupted night leaves a valid file.
    write_json_file(o.out_dir / "summary.json", suite);
  }
  suite["wall_seconds"] = json_figure(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  suite["exit_code"] = worst;
  write_json_file(o.out_dir / "summary.json", suite);
  for (const auto& row : suite["scenarios"])
    spdlog::info("{:<28} {}", row.value("name", row["file"].get<std::string>()), row["verdict"].get<std::string>());
  spdlog::info("suite summary: {}", (o.out_dir / "summary.json").string());
  return worst;
}

int list_devices_command() {
  const std::vector<std::string> devices = gpu::Device::list_devices();
  for (const std::string& d : devices) fmt::print("{}\n", d);
  return devices.empty() ? 3 : 0;
}

}  // namespace gi
