// `giharness nightly` (docs/design.md §10): every scenario of a suite (or of one
// shard of it), each compared with its baseline; summary.json per scenario
// and for the suite, JUnit XML and the HTML report. Exit 1 on a failed check
// or a regression; timing has a verdict of its own (reports/timing_verdict.h)
// that sets exit bit 4 only under --fail-on-timing.
//
// Isolation: each scenario runs in a child process of this binary
// (`giharness nightly-scenario`, hidden), with a wall-time limit and an
// optional memory limit, its log in <out>/<name>/run.log. A crash, a timeout,
// a lost device or bad input becomes that scenario's verdict (crashed,
// timeout, device_error, bad_input) and the night goes on.
//
// Interruption: the first SIGINT/SIGTERM lets the running scenario finish,
// marks the rest "not_run", writes the reports and exits 3; a second one
// kills at once (every file is written then renamed, so what is on disk stays
// valid). `--resume` keeps the completed scenarios of <out>/summary.json and
// runs the rest, and again those that crashed, timed out or lost the device.
//
// Seeds (--seeds N, core/seed_set.h): each scenario's seeds 1 … N−1 run after
// seed 0, each in a child of its own, into <out>/<name>/seed-<value>/; only
// seed 0 meets the baseline; a check whose verdict differs between seeds is
// flaky and so is its row (reports/seed_verdicts.h).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/cache_root.h"
#include "core/errors.h"
#include "core/json_input.h"
#include "core/reference/reference_cache.h"
#include "core/scenario.h"
#include "core/seed_set.h"
#include "gpu/device.h"
#include "app/child_process.h"
#include "app/commands.h"
#include "replay/wall_breakdown.h"
#include "reports/baseline_store.h"
#include "reports/change.h"
#include "reports/figures.h"
#include "reports/json_figures.h"
#include "reports/regression.h"
#include "reports/seed_verdicts.h"
#include "reports/suite_report.h"
#include "reports/timing_report.h"
#include "reports/timing_verdict.h"
#include "reports/summary.h"

namespace gi {
namespace {

std::atomic<int> g_stop_signal{0};


extern "C" void on_stop_signal(int sig) {
  g_stop_signal.store(sig);
  std::signal(sig, SIG_DFL);  // a second signal ends the process
}

// Installs the handlers for the nightly's lifetime only.
class StopSignals {
 public:
  StopSignals() {
    g_stop_signal.store(0);
    old_int_ = std::signal(SIGINT, on_stop_signal);
    old_term_ = std::signal(SIGTERM, on_stop_signal);
  }
  ~StopSignals() {
    std::signal(SIGINT, old_int_);
    std::signal(SIGTERM, old_term_);
  }
  bool requested() const { return g_stop_signal.load() != 0; }

 private:
  void (*old_int_)(int) = SIG_DFL;
  void (*old_term_)(int) = SIG_DFL;
};

std::vector<std::filesystem::path> suite_files(const std::filesystem::path& suite) {
  if (!std::filesystem::is_directory(suite))
    throw InputError(suite.string(), "", "expected a directory of scenario files");
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(suite))
    if (entry.is_regular_file() && entry.path().extension() == ".json" && entry.path().filename() != "schema.json")
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(suite.string(), "", "expected at least one *.json scenario");
  return files;
}

// A bug-museum scenario (Scenario::bug) is caught when every check it names
// failed: then its row passes (verdict "caught"); else it fails ("missed").
void judge_bug(const BugSpec& bug, nlohmann::json& row) {
  std::vector<std::string> silent;
  for (const std::string& name : bug.caught_by) {
    bool failed = false;
    for (const nlohmann::json& c : row.value("checks", nlohmann::json::array()))
      failed |= c.value("name", "") == name && c.value("verdict", "") == "fail";
    if (!failed) silent.push_back(name);
  }
  const bool caught = silent.empty();
  row["bug"] = {{"source", bug.source}, {"symptom", bug.symptom}, {"caught_by", bug.caught_by},
                {"caught", caught}, {"silent_checks", silent}};
  row["exit_code"] = caught ? 0 : 1;
  row["verdict"] = caught ? "caught" : "missed";
}

// Runs one scenario, in this process, and fills its suite row (the child's
// half of run_isolated). With --seeds, at seed `seed_index` of the scenario's
// seed set (core/seed_set.h): seed 0 is the scenario's own, in today's
// layout; seed k > 0 runs into <out>/<name>/seed-<value>/.
void run_one(const std::filesystem::path& file, const NightlyOptions& o, nlohmann::json& row,
             std::uint32_t seed_index = 0) {
  int code = 0;
  row.erase("error");
  std::optional<BugSpec> bug;
  try {
    const Scenario scenario = load_scenario(file);
    row["name"] = scenario.name;
    bug = scenario.bug;
    RunOptions ro;
    ro.device = o.device;
    std::filesystem::path rel = scenario.name;  // the run's out dir, relative to the suite's
    ro.quiet = true;
    ro.capture_failures = true;  // a failing check leaves a capture of its first failing frame
    // Speed against error at equal time (replay/equal_time.h) for the report;
    // a bug-museum scenario only asks whether its check catches the bug.
    // Not beside other scenarios (--jobs): the peers' budget is a time, and a loaded machine's is not the run's.
    ro.equal_time = !bug && o.jobs == 1;
    if (o.seeds) {
      const std::uint32_t seed = seed_set(scenario.seed, seed_index + 1).back();
      row["seed"] = seed;
      if (seed_index > 0) {
        ro.seed = seed;
        rel /= seed_dir_name(seed);
        ro.equal_time = false;  // the other seeds give verdicts; the report's speed against error is seed 0's
      }
    }
    ro.out_dir = o.out_dir / rel;
    const RunResult r = run_scenario(scenario, ro);
    code = r.exit_code;
    row["summary"] = (rel / "summary.json").string();
    row["checks"] = nlohmann::json::array();
    for (const CheckResult& c : r.checks)
      row["checks"].push_back({{"name", c.name},
                               {"verdict", to_string(c.verdict)},
                               {"message", c.message},
                               {"limits", c.stated_limits()},
                               {"first_failing_frame", c.first_failing_frame ? nlohmann::json(*c.first_failing_frame)
                                                                             : nlohmann::json(nullptr)}});
    // Where to start debugging: `giharness replay <out>/<capture>` (paths relative to the suite's out).
    row["failure_captures"] = nlohmann::json::array();
    for (const nlohmann::json& f : r.summary.value("failure_captures", nlohmann::json::array())) {
      nlohmann::json entry = {{"check", f["check"]}, {"frame", f["frame"]},
                              {"capture", (rel / f["capture"].get<std::string>()).string()}};
      // The failing capture's inspector page (app/inspect_command.h), which the
      // report links; a page that cannot be made costs the night nothing.
      const std::filesystem::path capture = ro.out_dir / f["capture"].get<std::string>();
      try {
        // The check's region outlined on the page where it judged one.
        InspectExtras extras;
        if (f.contains("region")) entry["region"] = extras.region = f["region"];
        if (f.contains("region_mask") && f["region_mask"].is_object()) {
          extras.region_mask_file = ro.out_dir / f["region_mask"].value("file", std::string());
          extras.region_mask_layer = f["region_mask"].value("layer", std::string());
          entry["region_mask"] = {{"file", (rel / f["region_mask"].value("file", std::string())).string()},
                                  {"layer", extras.region_mask_layer}};
        }
        write_inspect_page(capture, extras, capture / "inspect.html");
        entry["inspect"] = (rel / f["capture"].get<std::string>() / "inspect.html").string();
      } catch (const std::exception& e) {
        spdlog::warn("inspect {}: {}", capture.string(), e.what());
      }
      row["failure_captures"].push_back(entry);
    }
  } catch (const InputError& e) {
    code = 2;
    row["error"] = e.what();
  } catch (const DeviceError& e) {
    code = 3;
    row["error"] = e.what();
  } catch (const std::exception& e) {
    // One scenario's internal error must not lose the rest of the night.
    code = 3;
    row["error"] = std::string("internal error: ") + e.what();
  }
  row["exit_code"] = code;
  row["verdict"] = code == 0 ? "pass" : code == 1 ? "fail" : code == 2 ? "bad_input" : "error";
  if (bug && (code == 0 || code == 1)) judge_bug(*bug, row);
}

// Verdicts that say the scenario gave no result of its own making: --resume
// runs them again.
bool retried_on_resume(const nlohmann::json& row) {
  const std::string v = row.value("verdict", "");
  return v == "crashed" || v == "timeout" || v == "device_error";
}

// The wall-time limit of one scenario: its own timeout_seconds, else the
// suite's. Read with the guarded reader only; a file it refuses is the
// child's to report as bad input.
double scenario_timeout(const std::filesystem::path& file, double suite_default) {
  try {
    const nlohmann::json doc = read_json_input(file, "a scenario file");
    if (doc.is_object() && doc.contains("timeout_seconds") && doc["timeout_seconds"].is_number_unsigned() &&
        doc["timeout_seconds"].get<std::uint64_t>() > 0)
      return double(doc["timeout_seconds"].get<std::uint64_t>());
  } catch (const InputError&) {
  }
  return suite_default;
}

// Runs one scenario in a child process and fills its suite row from what
// the child wrote, or from how it ended when it wrote nothing. With --seeds,
// at seed `seed_index` of its set (run_one).
void run_isolated(const std::filesystem::path& file, const NightlyOptions& o, nlohmann::json& row,
                  std::uint32_t seed_index = 0) {
  const std::filesystem::path logs = o.out_dir / "logs";
  std::filesystem::create_directories(logs);
  const std::string stem = file.stem().string() + (seed_index > 0 ? ".seed" + std::to_string(seed_index) : "");
  const std::filesystem::path row_file = logs / (stem + ".row.json"), log = logs / (stem + ".log");
  std::filesystem::remove(row_file);
  std::vector<std::string> argv = {self_executable().string(), "nightly-scenario", file.string(), "--out",
                                   o.out_dir.string(), "--row", row_file.string()};
  if (o.device) argv.insert(argv.end(), {"--device", std::to_string(*o.device)});
  if (o.jobs > 1) argv.insert(argv.end(), {"--jobs", std::to_string(o.jobs)});
  if (o.seeds)
    argv.insert(argv.end(), {"--seeds", std::to_string(*o.seeds), "--seed-index", std::to_string(seed_index)});
  ChildLimits limits;
  limits.wall_seconds = scenario_timeout(file, o.scenario_timeout);
  if (o.memory_limit_mb) limits.memory_bytes = *o.memory_limit_mb << 20;
  const ChildEnd end = run_child(argv, log, limits, nullptr);

  for (const char* key : {"error", "checks", "failure_captures", "summary", "log", "log_tail", "reason"}) row.erase(key);
  nlohmann::json written;
  if (end.how == ChildEnd::How::exited && std::filesystem::exists(row_file)) {
    try {
      written = read_json_input(row_file, "the scenario process's result");
    } catch (const InputError&) {
    }
  }
  if (written.is_object()) {
    for (auto it = written.begin(); it != written.end(); ++it) row[it.key()] = it.value();
  } else {
    row["exit_code"] = 3;
    if (end.how == ChildEnd::How::timed_out) {
      row["verdict"] = "timeout";
      row["error"] = fmt::format("no result within {:.0f} s (the scenario's timeout_seconds, else --scenario-timeout): "
                                 "stopped with SIGTERM, then SIGKILL",
                                 limits.wall_seconds);
    } else if (end.how == ChildEnd::How::signalled) {
      row["verdict"] = "crashed";
      row["error"] = "the scenario's process was killed by " + signal_name(end.signal) +
                     (end.signal == SIGKILL && limits.memory_bytes
                          ? fmt::format(" (out of memory? its limit was {} MiB)", *o.memory_limit_mb)
                          : std::string());
    } else {
      row["verdict"] = "crashed";
      row["error"] = fmt::format("the scenario's process exited with code {} and left no result", end.exit_code);
    }
  }
  std::filesystem::remove(row_file);
  // The log goes beside the scenario's results when it got that far.
  std::filesystem::path kept = log;
  if (row.contains("name") && row["name"].is_string() && !row["name"].get<std::string>().empty()) {
    std::filesystem::path dir = o.out_dir / row["name"].get<std::string>();
    if (seed_index > 0 && row.contains("seed") && row["seed"].is_number_unsigned())
      dir /= seed_dir_name(row["seed"].get<std::uint32_t>());
    std::filesystem::create_directories(dir);
    kept = dir / "run.log";
    std::filesystem::rename(log, kept);
  }
  row["log"] = std::filesystem::relative(kept, o.out_dir).string();
  const std::string verdict = row.value("verdict", "");
  if (verdict != "pass" && verdict != "fail" && verdict != "caught" && verdict != "missed") row["log_tail"] = tail_of_file(kept, 20);
}

// Compares a completed scenario with its baseline: its figures within
// tolerance (a regression makes the row fail, exit 1, even when every check
// passed), then its bits against the exact baseline (reports/change.h; a
// change fails only under --fail-on-change).
// A timing regression is confirmed by running the scenario once more, in a
// process of its own (into <out>/<name>/timing-confirm/): a series stays
// regressed only if that run regresses it too (reports/timing_verdict.h,
// confirm_timings). Nothing of the second run but its timing is used.
void confirm_timing(TimingComparison& timing, const TimingSamples& base, const std::filesystem::path& file,
                    const std::string& name, const NightlyOptions& o) {
  NightlyOptions again = o;
  again.out_dir = o.out_dir / name / "timing-confirm";
  std::filesystem::create_directories(again.out_dir);
  nlohmann::json row = {{"file", file.string()}};
  run_isolated(file, again, row);
  TimingComparison second;  // not compared: no second run, so nothing repeats
  if (row.contains("summary")) {
    try {
      second = compare_timings(base, timing_samples(read_json_input(again.out_dir / row["summary"].get<std::string>(),
                                                                    "the confirmation run's summary.json")));
    } catch (const InputError& e) {
      spdlog::warn("{}: the timing confirmation run left no readable summary: {}", name, e.what());
    }
  }
  confirm_timings(timing, second);
  spdlog::info("{}: timing regression {} by a second run", name, timing.verdict == "regressed" ? "confirmed" : "not confirmed");
}

void compare_row(const nlohmann::json& summary, const std::filesystem::path& class_dir, const NightlyOptions& o,
                 nlohmann::json& row) {
  const std::string name = summary["scenario"]["name"];
  const std::optional<nlohmann::json> doc = read_baseline_document(class_dir, name);
  const std::filesystem::path run_rel = std::filesystem::path(row["summary"].get<std::string>()).parent_path();
  ChangeInputs change{doc, baseline_image_file(class_dir, name), summary, o.out_dir / run_rel,
                      o.out_dir / run_rel / "change", run_rel / "change"};
  row["change"] = detect_change(change);
  if (row["change"]["status"] == "changed" && o.fail_on_change) {
    row["change"]["fails"] = true;
    row["exit_code"] = std::max(row["exit_code"].get<int>(), 1);
    if (row["verdict"] == "pass" || row["verdict"] == "caught") row["verdict"] = "changed";
  }
  if (!doc) {
    row["baseline_status"] = "no_baseline";
    row["regressions"] = nlohmann::json::array();
    return;
  }
  // Speed, apart from correctness: its own verdict, never the row's
  // (reports/timing_verdict.h); fatal only through the suite's exit bit.
  const TimingSamples measured = timing_samples(summary);
  const TimingSamples base = doc->contains("timing_samples")
                                 ? TimingSamples::from_json((*doc)["timing_samples"], baseline_file(class_dir, name).string())
                                 : TimingSamples{};
  if (!measured.series.empty() || !base.series.empty()) {
    TimingComparison timing;
    if (o.jobs > 1) {
      // Side by side, a scenario's passes wait for the CPUs another's compile
      // holds, more than the per-frame load test sees (a pipeline total read
      // 2.3x its baseline in such a night).
      timing.reason = fmt::format("{} scenarios ran at once (--jobs {}): timing is judged one at a time", o.jobs, o.jobs);
    } else {
      timing = compare_timings(base, measured);
      if (timing.verdict == "regressed" && o.confirm_timing)
        confirm_timing(timing, base, row["file"].get<std::string>(), name, o);
    }
    row["timing"] = timing.to_json();
  }
  const ScenarioFigures baseline = baseline_figures(*doc, baseline_file(class_dir, name));
  const BaselineComparison cmp = compare_to_baseline(baseline, extract_figures(summary), load_tolerance_rules(class_dir));
  row["baseline_status"] = "compared";
  row["baseline"] = baseline_file(class_dir, name).string();
  row["figures_compared"] = cmp.compared;
  row["regressions"] = nlohmann::json::array();
  for (const FigureDelta& d : cmp.deltas) row["regressions"].push_back(d.to_json());
  if (cmp.regressions() > 0) {
    row["exit_code"] = std::max(row["exit_code"].get<int>(), 1);
    if (row["verdict"] == "pass" || row["verdict"] == "changed" || row["verdict"] == "caught") row["verdict"] = "regressed";
  }
}

// --seeds N: the scenario's seeds 1 … N−1, each in a process of its own
// (run_isolated), after seed 0 (`seed0`: its row before the baseline
// comparison); their verdicts go into `row` (reports/seed_verdicts.h).
// Nothing of theirs meets the baseline. False when a stop signal came between
// two seeds: the scenario is then not complete.
template <class Stop>
bool run_other_seeds(nlohmann::json& row, const nlohmann::json& seed0, const NightlyOptions& o, const Stop& stop) {
  const std::uint32_t count = *o.seeds;
  if (error_verdict(seed0.value("verdict", "")) || !seed0.contains("checks")) {
    row["seeds"] = {{"count", count},
                    {"skipped", fmt::format("seed 0 ended in {}: the other seeds were not run", seed0.value("verdict", "?"))}};
    return true;
  }
  std::vector<nlohmann::json> runs = {seed0};
  for (std::uint32_t k = 1; k < count; ++k) {
    if (stop.requested()) return false;
    const auto t0 = std::chrono::steady_clock::now();
    nlohmann::json r = {{"file", row["file"]}};
    run_isolated(row["file"].get<std::string>(), o, r, k);
    r["wall_seconds"] = json_figure(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    spdlog::info("  seed {} ({} of {}): {}", r.value("seed", 0u), k + 1, count, r.value("verdict", "?"));
    runs.push_back(std::move(r));
  }
  apply_seed_runs(row, runs);
  for (const nlohmann::json& c : row.value("checks", nlohmann::json::array()))
    if (c.value("seed_status", "") == "flaky")
      spdlog::warn("{}: check {} flaky: {}", row.value("name", "?"), c.value("name", "?"),
                   seed_verdict_list(row["seeds"]["values"].get<std::vector<std::uint32_t>>(),
                                     c["seed_verdicts"].get<std::vector<std::string>>()));
  if (row.contains("bug") && row["bug"].contains("seeds"))
    spdlog::info("{}: bug {}", row.value("name", "?"), row["bug"]["seeds"].value("text", ""));
  return true;
}

// --update-baseline: the references a scenario was judged against become
// seeds in <baseline root>/references (core/reference/reference_cache.h), so
// a fresh machine renders none that a baseline already holds.
ReferenceSeeds keep_seeds(const nlohmann::json& summary, const std::filesystem::path& baseline_root) {
  return keep_reference_seeds(summary.value("reference_entries", std::vector<std::string>()),
                              cache_root() / "reference", baseline_root / "references");
}

void log_seeds(const ReferenceSeeds& last, std::size_t added, const std::filesystem::path& baseline_root) {
  spdlog::info("reference seeds in {}: {} added, {} of another integrator version removed; {} entries, {:.2f} MB",
               (baseline_root / "references").string(), added, last.removed, last.entries,
               double(last.bytes) / (1024.0 * 1024.0));
}

// "i/n" with 1 ≤ i ≤ n.
std::pair<int, int> parse_shard(const std::string& text) {
  int i = 0, n = 0;
  char slash = 0;
  std::istringstream in(text);
  if (!(in >> i >> slash >> n) || slash != '/' || i < 1 || n < 1 || i > n || !in.eof())
    throw InputError("--shard", "", "expected i/n with 1 <= i <= n, got \"" + text + "\"");
  return {i, n};
}

std::string progress_line(std::size_t k, std::size_t total, const nlohmann::json& row, double seconds, double eta) {
  std::size_t passed = 0, checks = 0, regressions = 0;
  for (const auto& c : row.value("checks", nlohmann::json::array())) {
    ++checks;
    passed += c.value("verdict", "") == "pass";
  }
  for (const auto& d : row.value("regressions", nlohmann::json::array())) regressions += d.value("status", "") != "improved";
  std::string seeds;
  if (row.contains("seeds") && row["seeds"].contains("flaky_checks"))
    seeds = fmt::format("  seeds {}: {} flaky", row["seeds"].value("count", 0), row["seeds"]["flaky_checks"].size());
  return fmt::format("[{}/{}] {:<28} {:<9} checks {}/{}  regressions {}{}  {:.1f} s  (eta {:.0f} s)", k, total,
                     row.value("name", row.value("file", "?")), row.value("verdict", "?"), passed, checks, regressions,
                     seeds, seconds, eta);
}

}  // namespace

int run_nightly(const NightlyOptions& o) {
  // What measures time must run alone: baselines keep timing samples, and a
  // timing verdict needs a quiet machine.
  if (o.jobs > 1 && (o.update_baseline || o.add_timing_run || o.fail_on_timing))
    throw InputError("--jobs", "", fmt::format("1 with --update-baseline, --add-timing-run or --fail-on-timing (got {}): "
                                               "baselines and timing verdicts are measured one scenario at a time",
                                               o.jobs));
  if (o.slurm.tasks > 0) return submit_slurm_nightly(o);  // the shards run as Slurm jobs, not here
  std::vector<std::filesystem::path> files = suite_files(o.suite);
  nlohmann::json shard_info;
  if (!o.shard.empty()) {
    const auto [i, n] = parse_shard(o.shard);
    std::vector<std::filesystem::path> mine;
    for (std::size_t k = 0; k < files.size(); ++k)
      if (static_cast<int>(k % static_cast<std::size_t>(n)) == i - 1) mine.push_back(files[k]);
    files = mine;
    shard_info = {{"index", i}, {"count", n}};
  }

  nlohmann::json suite;
  const std::filesystem::path summary_path = o.out_dir / "summary.json";
  if (o.resume && std::filesystem::exists(summary_path)) {
    try {
      suite = nlohmann::json::parse(std::ifstream(summary_path));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(summary_path.string(), "", std::string("a nightly summary to resume (") + e.what() + ")");
    }
  }
  // Completed rows of a resumed night, by scenario file (run at as many seeds as asked now).
  std::map<std::string, nlohmann::json> done;
  const std::uint32_t seed_count = o.seeds.value_or(1);
  if (suite.is_object())
    for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array()))
      if (row.value("status", "") == "complete" && !retried_on_resume(row) &&
          row.value("seeds", nlohmann::json::object()).value("count", 1u) == seed_count &&
          (!row.contains("summary") || std::filesystem::exists(o.out_dir / row["summary"].get<std::string>())))
        done[row.value("file", "")] = row;

  const auto start = std::chrono::steady_clock::now();
  const std::string started_utc = utc_timestamp();
  suite = {{"schema_version", 1},
           {"suite", o.suite.string()},
           {"build", build_info()},
           {"baseline_dir", o.baseline_dir.string()},
           {"scenarios", nlohmann::json::array()}};
  if (!shard_info.is_null()) suite["shard"] = shard_info;
  if (o.seeds) suite["seeds"] = {{"count", *o.seeds}, {"rule", seed_rule_text()}};
  suite["jobs"] = o.jobs;
  for (const std::filesystem::path& file : files) {
    const auto it = done.find(file.string());
    suite["scenarios"].push_back(it != done.end() ? it->second
                                                  : nlohmann::json{{"file", file.string()}, {"status", "pending"}});
  }
  if (!done.empty()) spdlog::info("resuming: {} of {} scenarios already complete", done.size(), files.size());

  // The scenarios read their references' seeds from this night's baseline
  // root, where --update-baseline writes them (core/reference/reference_cache.h).
  ::setenv("GIHARNESS_REFERENCE_SEEDS", std::filesystem::absolute(o.baseline_dir / "references").c_str(), 1);
  // Scenarios side by side already keep the cores busy: each compiles its
  // shaders ahead (gpu/shader_prewarm.h) only on a share of two cores or
  // more, else not at all (on 2 cores at --jobs 2 the workers made the cold
  // night 604 s against 545 s without). The environment's setting wins.
  if (o.jobs > 1 && !std::getenv("GIHARNESS_SHADER_PREWARM_THREADS")) {
    const unsigned share = std::max(1u, std::thread::hardware_concurrency()) / unsigned(o.jobs);
    ::setenv("GIHARNESS_SHADER_PREWARM_THREADS", std::to_string(share >= 2 ? share : 0).c_str(), 1);
  }
  StopSignals stop;
  // Rows to run, in suite order; --jobs N runs N of them at once, each in a
  // process of its own. The suite document is only touched under `mu`: a
  // worker runs its scenario on a copy of its row and puts it back.
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < suite["scenarios"].size(); ++i)
    if (suite["scenarios"][i]["status"] != "complete") todo.push_back(i);
  std::mutex mu;
  std::size_t next = 0, ran = 0;
  bool halted = false;  // a stop signal came between two seeds: start nothing more
  ReferenceSeeds seeds;  // --update-baseline: the seed folder after the latest scenario
  std::size_t seeds_added = 0;
  const auto loop_start = std::chrono::steady_clock::now();
  const auto run_row = [&](std::size_t i) {
    nlohmann::json row;
    {
      const std::lock_guard lock(mu);
      row = suite["scenarios"][i];
    }
    const auto t0 = std::chrono::steady_clock::now();
    spdlog::info("[{}/{}] {} ...", i + 1, files.size(), row["file"].get<std::string>());
    run_isolated(row["file"].get<std::string>(), o, row);
    const nlohmann::json seed0 = o.seeds ? row : nlohmann::json();
    if (row.contains("summary")) {
      nlohmann::json summary;
      try {
        summary = read_json_input(o.out_dir / row["summary"].get<std::string>(), "the scenario's summary.json");
      } catch (const InputError& e) {
        row["error"] = e.what();
        row["exit_code"] = 3;
        row["verdict"] = "error";
      }
      if (summary.is_object()) {
        const nlohmann::json device = summary.value("device", nlohmann::json::object());
        const std::string cls = device_class(device);
        {
          const std::lock_guard lock(mu);
          if (!suite.contains("device") && !device.empty()) {
            suite["device"] = device;
            suite["device_class"] = cls;
          }
          add_wall_breakdown(suite["wall_breakdown"], summary.value("wall_breakdown", nlohmann::json()));
        }
        compare_row(summary, o.baseline_dir / cls, o, row);
        // Another process's view of the same tree: only where the bits say it is the same tree.
        if (o.add_timing_run && row.contains("change") && row["change"].value("status", "") == "unchanged") {
          const std::string why_not = add_timing_run(o.baseline_dir / cls, summary);
          if (why_not.empty()) row["timing_run_added"] = true;
          else spdlog::warn("{}: timing run not added to its baseline: {}", row.value("name", "?"), why_not);
        }
        if (o.update_baseline) {
          write_baseline(o.baseline_dir / cls, summary,
                         o.out_dir / std::filesystem::path(row["summary"].get<std::string>()).parent_path());
          const std::lock_guard lock(mu);
          seeds = keep_seeds(summary, o.baseline_dir);
          seeds_added += seeds.added;
        }
      }
    }
    const bool complete = !o.seeds || run_other_seeds(row, seed0, o, stop);
    const std::lock_guard lock(mu);
    if (!complete) {
      suite["scenarios"][i] = {{"file", row["file"]}, {"status", "pending"}};  // --resume runs all its seeds again
      halted = true;
      return;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    row["wall_seconds"] = json_figure(seconds);
    row["status"] = "complete";
    ++ran;
    // What is left, at the pace of this night so far (the jobs side by side included).
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
    const double eta = elapsed / double(ran) * double(todo.size() - ran);
    spdlog::log(row.value("exit_code", 0) == 0 ? spdlog::level::info : spdlog::level::err, "{}",
                progress_line(i + 1, files.size(), row, seconds, eta));
    suite["scenarios"][i] = std::move(row);
    // Rewritten after every scenario, so an interrupted night leaves a valid file.
    write_json_file(summary_path, suite);
  };
  std::exception_ptr failure;  // the first worker's error, rethrown once every running scenario has ended
  const auto worker = [&] {
    for (;;) {
      std::size_t i = 0;
      {
        const std::lock_guard lock(mu);
        if (halted || stop.requested() || next == todo.size()) return;
        i = todo[next++];
      }
      try {
        run_row(i);
      } catch (...) {
        const std::lock_guard lock(mu);
        if (!failure) failure = std::current_exception();
        halted = true;
        return;
      }
    }
  };
  const std::size_t jobs = std::min<std::size_t>(o.jobs, std::max<std::size_t>(todo.size(), 1));
  if (jobs > 1) spdlog::info("{} scenarios at a time, each in a process of its own", jobs);
  std::vector<std::thread> workers;
  for (std::size_t w = 1; w < jobs; ++w) workers.emplace_back(worker);
  worker();
  for (std::thread& t : workers) t.join();
  if (failure) std::rethrow_exception(failure);
  const bool unfinished = std::any_of(suite["scenarios"].begin(), suite["scenarios"].end(),
                                      [](const nlohmann::json& r) { return r["status"] != "complete"; });
  if (stop.requested() && unfinished) {  // a signal during the last scenario loses nothing
    suite["interrupted"] = true;
    for (nlohmann::json& row : suite["scenarios"])
      if (row["status"] != "complete") row["status"] = "not_run";
    spdlog::warn("interrupted by signal {}: {} scenarios not run; `--resume` continues", g_stop_signal.load(),
                 std::count_if(suite["scenarios"].begin(), suite["scenarios"].end(),
                               [](const nlohmann::json& r) { return r["status"] != "complete"; }));
  }
  std::error_code ec;
  std::filesystem::remove(o.out_dir / "logs", ec);  // only if empty: logs of scenarios that never got a name stay
  suite["wall_seconds"] = json_figure(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (suite.contains("wall_breakdown") && suite["wall_breakdown"].is_object())
    spdlog::info("the scenarios' runs (first seed; timing confirmations not counted): {}",
                 wall_breakdown_line(suite["wall_breakdown"]));
  if (!suite.contains("device_class")) suite["device_class"] = "unknown";
  const std::filesystem::path class_dir = o.baseline_dir / suite["device_class"].get<std::string>();
  suite["baseline_status"] = std::filesystem::is_directory(class_dir) ? "found" : "none for this device class";
  if (o.update_baseline) {
    const ImageBudget budget = enforce_image_budget(class_dir, o.image_budget_mb);
    spdlog::info("baselines written to {}; its images: {:.2f} MB of the {} MB budget", class_dir.string(),
                 double(budget.bytes) / (1024.0 * 1024.0), o.image_budget_mb);
    for (const std::string& name : budget.dropped)
      spdlog::warn("baseline image of {} dropped (over the budget): its changes show without relMSE or heat map", name);
    log_seeds(seeds, seeds_added, o.baseline_dir);
  }
  suite["fail_on_change"] = o.fail_on_change;
  suite["fail_on_timing"] = o.fail_on_timing;
  attach_timing_history(suite, o.history_dir, o.history_nights);
  const int code = finish_suite(o.out_dir, suite, o.junit);
  record_timing_history(suite, o.history_dir, started_utc);
  for (const nlohmann::json& row : suite["scenarios"])
    for (const nlohmann::json& t : row.value("timing", nlohmann::json::object()).value("series", nlohmann::json::array()))
      if (t.value("verdict", "") == "regressed")
        spdlog::log(o.fail_on_timing ? spdlog::level::err : spdlog::level::warn,
                    "timing regressed: {} {}: {} ms against {} ms, ratio {} (interval {})", row.value("name", "?"),
                    t.value("name", "?"), t["measured_ms"].dump(), t["baseline_ms"].dump(), t["ratio"].dump(),
                    t["interval"].dump());
  for (const nlohmann::json& row : suite["scenarios"])
    if (row.contains("change") && row["change"].value("status", "") == "changed")
      spdlog::log(o.fail_on_change ? spdlog::level::err : spdlog::level::warn,
                  "changed: {} (first differing frame {}, buffers {}, relMSE {})", row.value("name", "?"),
                  row["change"]["first_differing_frame"].dump(), row["change"]["differing_buffers"].dump(),
                  row["change"]["image"].is_object() ? row["change"]["image"]["relmse"].dump() : "n/a");
  const nlohmann::json& changes = suite["changes"];
  std::size_t regressions = 0;
  for (const nlohmann::json& row : suite["scenarios"])
    for (const auto& d : row.value("regressions", nlohmann::json::array())) {
      if (d.value("status", "") == "improved") continue;
      ++regressions;
      spdlog::error("regression: {} {}: baseline {}, measured {}, tolerance {}", row.value("name", "?"),
                    d.value("metric", ""), d["baseline"].dump(), d["measured"].dump(), d.value("tolerance", ""));
    }
  if (suite.contains("bugs")) {
    for (const nlohmann::json& row : suite["scenarios"])
      if (row.contains("bug") && !row["bug"].value("caught", false)) {
        if (row["bug"].contains("seeds"))
          spdlog::error("missed bug: {} ({}): {}", row.value("name", "?"), row["bug"].value("source", ""),
                        row["bug"]["seeds"].value("text", ""));
        else
          spdlog::error("missed bug: {} ({}): {} did not fail", row.value("name", "?"), row["bug"].value("source", ""),
                        row["bug"].value("silent_checks", nlohmann::json::array()).dump());
      }
    const nlohmann::json& b = suite["bugs"];
    spdlog::info("bugs: {} caught, {} missed: catch rate {:.0f} %", b["caught"].get<int>(), b["missed"].get<int>(),
                 100.0 * b["catch_rate"].get<double>());
    if (b.contains("seed_runs"))
      spdlog::info("bugs over seeds: {} flaky (caught at some seeds only); caught in {} of {} seed runs ({:.0f} %)",
                   b["flaky"].get<int>(), b["seed_runs_caught"].get<int>(), b["seed_runs"].get<int>(),
                   100.0 * b["seed_catch_rate"].get<double>());
  }
  if (suite.contains("seeds") && suite["seeds"].contains("flaky_checks")) {
    const nlohmann::json& t = suite["seeds"];
    for (const nlohmann::json& f : t["flaky_checks"])
      spdlog::error("flaky: {} {}: {}", f.value("scenario", "?"), f.value("check", "?"),
                    seed_verdict_list(f["seeds"].get<std::vector<std::uint32_t>>(),
                                      f["verdicts"].get<std::vector<std::string>>()));
    spdlog::info("seeds: {} per scenario; {} flaky checks in {} scenarios", t.value("count", 0u),
                 t["flaky_checks"].size(), t.value("flaky_scenarios", 0u));
  }
  if (suite["baseline_status"] != "found")
    spdlog::warn("no baselines in {} (create them with `giharness nightly --update-baseline` or `giharness baseline "
                 "update --from {}`)", class_dir.string(), o.out_dir.string());
  const nlohmann::json& timing = suite["timing"];
  spdlog::info("timing: {} scenarios regressed, {} improved, {} unchanged, {} not compared ({} machine loaded){}",
               timing["regressed"].get<int>(), timing["improved"].get<int>(), timing["unchanged"].get<int>(),
               timing["not_compared"].get<int>(), timing["loaded"].get<int>(), o.fail_on_timing ? " (--fail-on-timing: exit bit 4)" : " (reported only)");
  spdlog::info("suite {}: exit {}, {} regressions; {} unchanged, {} changed, {} without an exact baseline; report {}; "
               "junit {}",
               suite["verdict"].get<std::string>(), code, regressions, changes["unchanged"].get<int>(),
               changes["changed"].get<int>(), changes["no_exact_baseline"].get<int>(),
               (o.out_dir / "report.html").string(), suite["junit"].get<std::string>());
  return code;
}

int run_nightly_scenario(const NightlyScenarioOptions& o) {
  nlohmann::json row = {{"file", o.scenario.string()}};
  // A hung or lost GPU ends this process (Device::submit_and_wait): leave the
  // nightly a row that says so first.
  gpu::Device::set_fault_handler([&](const std::string& message) {
    row["exit_code"] = 3;
    row["verdict"] = "device_error";
    row["error"] = message;
    write_json_file(o.row, row);
  });
  NightlyOptions options;
  options.out_dir = o.out_dir;
  options.device = o.device;
  options.seeds = o.seeds;
  options.jobs = o.jobs;
  if (o.seeds && o.seed_index >= *o.seeds)
    throw InputError("--seed-index", "", fmt::format("an index below --seeds {}", *o.seeds));
  run_one(o.scenario, options, row, o.seed_index);
  gpu::Device::set_fault_handler(nullptr);
  write_json_file(o.row, row);
  return row["exit_code"].get<int>();
}

int run_baseline_update(const BaselineUpdateOptions& o) {
  const std::filesystem::path summary_path = o.from / "summary.json";
  nlohmann::json suite;
  try {
    suite = nlohmann::json::parse(std::ifstream(summary_path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(summary_path.string(), "", std::string("a nightly summary (") + e.what() + ")");
  }
  std::size_t written = 0, seeds_added = 0;
  ReferenceSeeds seeds;
  std::set<std::filesystem::path> classes;
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array())) {
    if (row.value("status", "") != "complete" || row.contains("error") || !row.contains("summary")) continue;
    const nlohmann::json s = nlohmann::json::parse(std::ifstream(o.from / row["summary"].get<std::string>()));
    const std::filesystem::path class_dir = o.baseline_dir / device_class(s.value("device", nlohmann::json::object()));
    write_baseline(class_dir, s, o.from / std::filesystem::path(row["summary"].get<std::string>()).parent_path());
    spdlog::info("baseline {}", baseline_file(class_dir, s["scenario"]["name"]).string());
    seeds = keep_seeds(s, o.baseline_dir);
    seeds_added += seeds.added;
    classes.insert(class_dir);
    ++written;
  }
  if (written == 0) throw InputError(summary_path.string(), "/scenarios", "at least one completed scenario");
  for (const std::filesystem::path& class_dir : classes) {
    const ImageBudget budget = enforce_image_budget(class_dir, o.image_budget_mb);
    spdlog::info("{}: images {:.2f} MB of the {} MB budget", class_dir.string(), double(budget.bytes) / (1024.0 * 1024.0),
                 o.image_budget_mb);
    for (const std::string& name : budget.dropped) spdlog::warn("baseline image of {} dropped (over the budget)", name);
  }
  log_seeds(seeds, seeds_added, o.baseline_dir);
  return 0;
}

int list_devices_command() {
  const std::vector<std::string> devices = gpu::Device::list_devices();
  for (const std::string& d : devices) fmt::print("{}\n", d);
  return devices.empty() ? 3 : 0;
}

}  // namespace gi
