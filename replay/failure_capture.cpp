#include "replay/failure_capture.h"

#include <algorithm>
#include <map>
#include <set>

#include <spdlog/spdlog.h>

#include "core/check_catalog.h"
#include "replay/capture.h"

namespace gi {

nlohmann::json capture_failing_frames(const Scenario& scenario, const RunOptions& run, std::uint32_t frames,
                                      const std::vector<std::uint32_t>& captured, std::vector<CheckResult>& checks) {
  std::map<std::string, std::uint32_t> frame_of;  // failing check → frame to capture
  for (const CheckResult& c : checks)
    if (!c.passed()) frame_of[c.name] = c.first_failing_frame.value_or(frames - 1);
  std::set<std::uint32_t> wanted;
  for (const auto& [check, frame] : frame_of)
    if (std::find(captured.begin(), captured.end(), frame) == captured.end()) wanted.insert(frame);

  if (!wanted.empty()) {
    // The full length again: checks' parameters name frames of the whole run.
    RunOptions rerun = run;
    rerun.capture.assign(wanted.begin(), wanted.end());
    rerun.capture_failures = false;
    rerun.quiet = true;
    rerun.out_dir = run.out_dir / ".failure_rerun";
    std::filesystem::remove_all(rerun.out_dir);
    Scenario same = scenario;
    same.capture.clear();
    // Its own repeats would only run the scenario twice more.
    drop_rerunning_checks(same);
    spdlog::info("{}: re-running to capture the first failing frame(s) of its failing checks", scenario.name);
    run_scenario(same, rerun);
    for (std::uint32_t f : wanted) {
      const std::filesystem::path to = run.out_dir / capture_folder(f);
      std::filesystem::create_directories(to.parent_path());
      std::filesystem::remove_all(to);
      std::filesystem::rename(rerun.out_dir / capture_folder(f), to);
    }
    std::filesystem::remove_all(rerun.out_dir);
  }
  nlohmann::json list = nlohmann::json::array();
  for (CheckResult& c : checks) {
    const auto it = frame_of.find(c.name);
    if (it == frame_of.end()) continue;
    c.evidence.push_back(capture_folder(it->second).string());
    nlohmann::json entry = {{"check", c.name}, {"frame", it->second}, {"capture", capture_folder(it->second).string()}};
    // The region the check judged, for the inspector to outline (CheckResult::region).
    if (!c.region.is_null()) entry["region"] = c.region;
    if (!c.region_mask.is_null()) entry["region_mask"] = c.region_mask;
    list.push_back(entry);
  }
  return list;
}

}  // namespace gi
