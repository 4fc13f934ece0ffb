// `giharness merge DIR... --out DIR`: the shards of a nightly (`--shard i/n`,
// run on as many machines) become one suite: their scenario folders are
// copied under --out, the rows are combined in scenario-file order, and the
// suite summary, JUnit XML and HTML report are written as one night's.
#include <algorithm>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "app/commands.h"
#include "reports/suite_report.h"
#include "reports/summary.h"
#include "reports/timing_report.h"

namespace gi {
namespace {

nlohmann::json read_suite(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "summary.json";
  try {
    std::ifstream in(file);
    if (!in) throw InputError(file.string(), "", "a nightly summary (the file does not exist)");
    nlohmann::json j = nlohmann::json::parse(in);
    if (!j.contains("scenarios") || !j["scenarios"].is_array())
      throw InputError(file.string(), "/scenarios", "a list of scenario rows");
    return j;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string(), "", std::string("a nightly summary (") + e.what() + ")");
  }
}

}  // namespace

int run_merge(const MergeOptions& o) {
  const std::string started_utc = utc_timestamp();
  nlohmann::json merged = {{"schema_version", 1}, {"build", build_info()}, {"scenarios", nlohmann::json::array()},
                           {"merged_from", nlohmann::json::array()}};
  std::set<std::string> seen;
  double wall = 0;
  std::filesystem::create_directories(o.out_dir);
  for (const std::filesystem::path& dir : o.inputs) {
    const nlohmann::json suite = read_suite(dir);
    for (const char* key : {"suite", "device", "device_class", "baseline_dir", "baseline_status", "fail_on_change",
                            "fail_on_timing", "seeds"})
      if (!merged.contains(key) && suite.contains(key)) merged[key] = suite[key];
    if (suite.contains("device_class") && merged["device_class"] != suite["device_class"])
      spdlog::warn("merge: {} ran on device class {}, the first shard on {}: timings are not comparable",
                   dir.string(), suite["device_class"].dump(), merged["device_class"].dump());
    if (suite.value("interrupted", false)) merged["interrupted"] = true;
    merged["merged_from"].push_back({{"dir", dir.string()}, {"shard", suite.value("shard", nlohmann::json())}});
    if (suite.contains("wall_seconds") && suite["wall_seconds"].is_number()) wall += suite["wall_seconds"].get<double>();
    for (const nlohmann::json& row : suite["scenarios"]) {
      const std::string file = row.value("file", "");
      if (!seen.insert(file).second)
        throw InputError((dir / "summary.json").string(), "/scenarios",
                         fmt::format("each scenario in one shard only; {} is in two", file));
      if (row.contains("summary")) {
        const std::filesystem::path rel = std::filesystem::path(row["summary"].get<std::string>()).parent_path();
        const std::filesystem::path from = dir / rel, to = o.out_dir / rel;
        if (std::filesystem::weakly_canonical(from) != std::filesystem::weakly_canonical(to)) {
          std::filesystem::remove_all(to);
          std::filesystem::create_directories(to.parent_path());
          std::filesystem::copy(from, to, std::filesystem::copy_options::recursive);
        }
      }
      merged["scenarios"].push_back(row);
    }
  }
  std::sort(merged["scenarios"].begin(), merged["scenarios"].end(),
            [](const nlohmann::json& a, const nlohmann::json& b) { return a.value("file", "") < b.value("file", ""); });
  merged["wall_seconds"] = wall;  // machine time of all shards together
  attach_timing_history(merged, o.history_dir, o.history_nights);
  const int code = finish_suite(o.out_dir, merged, o.junit);
  record_timing_history(merged, o.history_dir, started_utc);
  spdlog::info("merged {} shards, {} scenarios: {} (exit {}); report {}", o.inputs.size(), merged["scenarios"].size(),
               merged["verdict"].get<std::string>(), code, (o.out_dir / "report.html").string());
  return code;
}

}  // namespace gi
