#include "reports/seed_verdicts.h"

#include <algorithm>

#include <fmt/format.h>

namespace gi {

std::string seed_status(const std::vector<std::string>& verdicts) {
  if (verdicts.empty()) return "missing";
  const std::size_t passed = std::count(verdicts.begin(), verdicts.end(), std::string("pass"));
  if (passed == verdicts.size()) return "pass";
  if (passed > 0) return "flaky";
  return std::all_of(verdicts.begin(), verdicts.end(), [&](const std::string& v) { return v == verdicts[0]; })
             ? verdicts[0]
             : "fail";
}

bool error_verdict(const std::string& v) {
  return v == "bad_input" || v == "crashed" || v == "timeout" || v == "device_error" || v == "error";
}

std::string seed_verdict_list(const std::vector<std::uint32_t>& seeds, const std::vector<std::string>& verdicts,
                              std::size_t limit) {
  std::string out;
  const std::size_t n = std::min(seeds.size(), verdicts.size());
  for (std::size_t k = 0; k < n && k < limit; ++k)
    out += fmt::format("{}seed {} {}", out.empty() ? "" : ", ", seeds[k], verdicts[k]);
  if (n > limit) out += fmt::format(", … {} more", n - limit);
  return out;
}

namespace {

// The verdict of check `name` in one run's check list; without it, the run's
// own verdict when the run gave no result (a crash, bad input), else "missing".
std::string verdict_in(const nlohmann::json& run, const std::string& name) {
  for (const nlohmann::json& c : run.value("checks", nlohmann::json::array()))
    if (c.value("name", "") == name) return c.value("verdict", "fail");
  const std::string v = run.value("verdict", "");
  return error_verdict(v) ? v : "missing";
}

std::vector<std::string> check_names(const std::vector<nlohmann::json>& runs) {
  std::vector<std::string> names;
  for (const nlohmann::json& run : runs)
    for (const nlohmann::json& c : run.value("checks", nlohmann::json::array())) {
      const std::string n = c.value("name", "?");
      if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    }
  return names;
}

std::vector<std::uint32_t> seeds_of(const std::vector<nlohmann::json>& runs) {
  std::vector<std::uint32_t> seeds;
  for (const nlohmann::json& r : runs) seeds.push_back(r.value("seed", 0u));
  return seeds;
}

}  // namespace

nlohmann::json seed_set_summary(const nlohmann::json& scenario, std::uint32_t base_seed,
                                const std::vector<nlohmann::json>& runs) {
  const std::vector<std::uint32_t> seeds = seeds_of(runs);
  nlohmann::json out = {{"schema_version", 1},
                        {"kind", "seed_set"},
                        {"scenario", scenario},
                        {"base_seed", base_seed},
                        {"seeds", seeds},
                        {"runs", nlohmann::json::array()},
                        {"checks", nlohmann::json::array()}};
  int worst = 0;
  for (const nlohmann::json& r : runs) {
    const std::string dir = r.value("dir", "");
    out["runs"].push_back({{"seed", r.value("seed", 0u)},
                           {"dir", dir},
                           {"summary", dir + "/summary.json"},
                           {"exit_code", r.value("exit_code", 1)}});
    worst = std::max(worst, r.value("exit_code", 1));
  }
  bool any_flaky = false, all_pass = true;
  for (const std::string& name : check_names(runs)) {
    nlohmann::json check = {{"name", name}, {"verdicts", nlohmann::json::array()}, {"per_seed", nlohmann::json::array()}};
    std::vector<std::string> verdicts;
    std::size_t passed = 0;
    for (const nlohmann::json& r : runs) {
      nlohmann::json entry = {{"seed", r.value("seed", 0u)}, {"verdict", "missing"}};
      for (const nlohmann::json& c : r.value("checks", nlohmann::json::array()))
        if (c.value("name", "") == name) {
          entry["verdict"] = c.value("verdict", "fail");
          entry["message"] = c.value("message", "");
          if (c.contains("figures")) entry["figures"] = c["figures"];  // as the check wrote them
        }
      verdicts.push_back(entry["verdict"]);
      passed += entry["verdict"] == "pass";
      check["verdicts"].push_back(entry["verdict"]);
      check["per_seed"].push_back(entry);
    }
    const std::string status = seed_status(verdicts);
    check["status"] = status;
    check["passed_at"] = passed;
    check["seeds"] = runs.size();
    any_flaky |= status == "flaky";
    all_pass &= status == "pass";
    out["checks"].push_back(check);
  }
  // A check that did not pass at every seed fails the run (flaky included).
  const int code = all_pass ? std::max(worst, 0) : std::max(worst, 1);
  out["verdict"] = any_flaky ? "flaky" : all_pass && code == 0 ? "pass" : "fail";
  out["exit_code"] = code;
  return out;
}

void apply_seed_runs(nlohmann::json& row, const std::vector<nlohmann::json>& runs) {
  const std::vector<std::uint32_t> seeds = seeds_of(runs);
  nlohmann::json info = {{"count", runs.size()}, {"values", seeds}, {"runs", nlohmann::json::array()}};
  int worst = row.value("exit_code", 0);
  for (const nlohmann::json& r : runs) {
    nlohmann::json entry = {{"seed", r.value("seed", 0u)}, {"verdict", r.value("verdict", "?")},
                            {"exit_code", r.value("exit_code", 3)}};
    for (const char* key : {"summary", "log", "error", "wall_seconds"})
      if (r.contains(key)) entry[key] = r[key];
    info["runs"].push_back(entry);
    worst = std::max(worst, r.value("exit_code", 3));
  }
  std::vector<std::string> statuses;
  info["flaky_checks"] = nlohmann::json::array();
  if (row.contains("checks"))
    for (nlohmann::json& c : row["checks"]) {
      const std::string name = c.value("name", "?");
      std::vector<std::string> verdicts;
      for (const nlohmann::json& r : runs) verdicts.push_back(verdict_in(r, name));
      c["seed_verdicts"] = verdicts;
      c["seed_status"] = seed_status(verdicts);
      statuses.push_back(c["seed_status"]);
      if (c["seed_status"] == "flaky") info["flaky_checks"].push_back(name);
    }
  const std::string verdict = row.value("verdict", "");
  bool flaky = false;
  if (row.contains("bug") && row["bug"].is_object()) {
    // The bug museum: the bug is caught at a seed when that run's row says so.
    nlohmann::json& bug = row["bug"];
    nlohmann::json caught_at = nlohmann::json::array(), missed_at = nlohmann::json::array();
    for (const nlohmann::json& r : runs) (r.value("verdict", "") == "caught" ? caught_at : missed_at).push_back(r.value("seed", 0u));
    const std::size_t caught = caught_at.size();
    bug["seeds"] = {{"caught", caught},
                    {"count", runs.size()},
                    {"caught_at", caught_at},
                    {"missed_at", missed_at},
                    {"text", fmt::format("caught at {} of {} seeds", caught, runs.size())}};
    bug["catch_rate"] = runs.empty() ? 0.0 : double(caught) / double(runs.size());
    bug["caught"] = caught == runs.size();
    flaky = caught > 0 && caught < runs.size();
  } else {
    flaky = !info["flaky_checks"].empty();
  }
  const bool all_pass = std::all_of(statuses.begin(), statuses.end(), [](const std::string& s) { return s == "pass"; });
  info["status"] = flaky ? "flaky" : (row.contains("bug") ? row["bug"].value("caught", false) : all_pass) ? "pass" : "fail";
  if (flaky) worst = std::max(worst, 1);
  if (flaky && !error_verdict(verdict)) row["verdict"] = "flaky";
  row["exit_code"] = worst;
  row["seeds"] = info;
}

nlohmann::json seed_tally(const nlohmann::json& suite) {
  nlohmann::json checks = nlohmann::json::array();
  std::size_t scenarios = 0, rows = 0;
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array())) {
    if (!row.contains("seeds")) continue;
    ++rows;
    scenarios += row.value("verdict", "") == "flaky";
    const nlohmann::json values = row["seeds"].value("values", nlohmann::json::array());
    // A bug-museum row's other checks only inform: its catching checks count.
    const nlohmann::json caught_by = row.value("bug", nlohmann::json::object()).value("caught_by", nlohmann::json());
    auto counts = [&](const std::string& check) {
      return !caught_by.is_array() || std::find(caught_by.begin(), caught_by.end(), check) != caught_by.end();
    };
    for (const nlohmann::json& c : row.value("checks", nlohmann::json::array()))
      if (c.value("seed_status", "") == "flaky" && counts(c.value("name", "")))
        checks.push_back({{"scenario", row.value("name", "?")}, {"check", c.value("name", "?")}, {"seeds", values},
                          {"verdicts", c["seed_verdicts"]}});
  }
  if (rows == 0) return nullptr;
  return {{"scenarios_run_at_seeds", rows}, {"flaky_scenarios", scenarios}, {"flaky_checks", checks}};
}

}  // namespace gi
