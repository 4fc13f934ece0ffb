// `giharness nightly --slurm N`: writes the job array and the merge
// job (app/slurm_job.h) into <out>/slurm/ and submits them with
// sbatch, the merge depending on the array. --slurm-dry-run only writes them
// and prints the commands. Bad flags are exit 2; no sbatch, or a submission
// sbatch refused, is exit 3 (the machine, not the input, is at fault).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "app/child_process.h"
#include "app/commands.h"
#include "app/slurm_job.h"

namespace gi {
namespace {

std::filesystem::path absolute_clean(const std::filesystem::path& p) {
  return std::filesystem::absolute(p).lexically_normal();
}

// The scenarios the nightly would run (its rule: *.json but schema.json), to
// refuse more tasks than scenarios: an empty shard is a task for nothing.
std::size_t scenario_count(const std::filesystem::path& suite) {
  if (!std::filesystem::is_directory(suite))
    throw InputError(suite.string(), "", "expected a directory of scenario files (--suite)");
  std::size_t n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(suite))
    n += entry.is_regular_file() && entry.path().extension() == ".json" && entry.path().filename() != "schema.json";
  return n;
}

SlurmJobSpec spec_of(const NightlyOptions& o) {
  if (!o.shard.empty())
    throw InputError("--shard", "", "expected no --shard with --slurm (each array task is one shard)");
  if (o.update_baseline)
    throw InputError("--update-baseline", "",
                     "expected no --update-baseline with --slurm (shards would write one device class's folder at "
                     "once); run `giharness baseline update --from <out>` after the merge");
  const NightlySlurmOptions& so = o.slurm;
  SlurmJobSpec s;
  s.giharness = self_executable();
  s.suite = absolute_clean(o.suite);
  s.out_dir = absolute_clean(o.out_dir);
  s.baseline_dir = absolute_clean(o.baseline_dir);
  if (!o.junit.empty()) s.junit = absolute_clean(o.junit);
  s.tasks = so.tasks;
  s.partition = so.partition;
  s.time_limit = so.time_limit;
  s.cpus_per_task = so.cpus_per_task;
  s.gres = so.gres;
  s.sbatch_args = so.sbatch_args;
  s.device = o.device;
  s.resume = o.resume;
  s.warn_seconds = so.warn_seconds;
  s.max_requeues = so.max_requeues;
  if (o.fail_on_change) s.nightly_args.push_back("--fail-on-change");
  if (o.add_timing_run) s.nightly_args.push_back("--add-timing-run");
  if (!o.confirm_timing) s.nightly_args.push_back("--no-timing-confirm");  // one scenario's file per task: no two write one
  // Timing is judged per shard and made fatal by the merge, which copies the flag from the shards.
  if (o.fail_on_timing) s.nightly_args.push_back("--fail-on-timing");
  // One history entry per night: the merged night's, not each shard's.
  if (!o.history_dir.empty())
    s.merge_args.insert(s.merge_args.end(), {"--history", absolute_clean(o.history_dir).string(), "--history-nights",
                                             std::to_string(o.history_nights)});
  s.nightly_args.insert(s.nightly_args.end(), {"--scenario-timeout", fmt::format("{}", o.scenario_timeout)});
  // Each task runs its scenarios at every seed; the merge copies each scenario's folder (seed-<value>/ inside it).
  if (o.seeds) s.nightly_args.insert(s.nightly_args.end(), {"--seeds", std::to_string(*o.seeds)});
  if (o.jobs > 1) s.nightly_args.insert(s.nightly_args.end(), {"--jobs", std::to_string(o.jobs)});  // within each task
  if (o.memory_limit_mb) s.nightly_args.insert(s.nightly_args.end(), {"--memory-limit-mb", std::to_string(*o.memory_limit_mb)});
  check_spec(s);
  const std::size_t scenarios = scenario_count(s.suite);
  if (scenarios == 0) throw InputError(s.suite.string(), "", "expected at least one *.json scenario");
  if (static_cast<std::size_t>(s.tasks) > scenarios)
    throw InputError("--slurm", "",
                     fmt::format("expected at most {} tasks (the suite's scenarios), got {}", scenarios, s.tasks));
  return s;
}

std::string command_line(const std::vector<std::string>& argv) {
  std::string text;
  for (const std::string& a : argv) text += (text.empty() ? "" : " ") + shell_quote(a);
  return text;
}

// sbatch by PATH, as a shell would find it.
std::optional<std::filesystem::path> find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / name;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

// Runs one sbatch; its job id, or nullopt after printing why not.
std::optional<std::string> submit(std::vector<std::string> argv, const std::filesystem::path& sbatch,
                                  const std::filesystem::path& log) {
  argv[0] = sbatch.string();
  ChildLimits limits;
  limits.wall_seconds = 120;  // sbatch retries an unreachable controller for a while, not for ever
  const ChildEnd end = run_child(argv, log, limits, nullptr);
  const std::string output = tail_of_file(log, 50);
  const std::optional<std::string> id = end.how == ChildEnd::How::exited && end.exit_code == 0
                                            ? parsable_job_id(output)
                                            : std::nullopt;
  if (!id)
    std::fprintf(stderr, "giharness: nightly --slurm: `%s` failed (%s):\n%s", command_line(argv).c_str(),
                 end.how == ChildEnd::How::exited ? fmt::format("exit {}", end.exit_code).c_str()
                 : end.how == ChildEnd::How::timed_out ? "no answer within 120 s"
                                                       : signal_name(end.signal).c_str(),
                 output.c_str());
  return id;
}

}  // namespace

int submit_slurm_nightly(const NightlyOptions& o) {
  const SlurmJobSpec spec = spec_of(o);
  std::filesystem::create_directories(slurm_dir(spec));
  for (const auto& [path, text] : {std::pair{array_script_path(spec), array_script(spec)},
                                   std::pair{merge_script_path(spec), merge_script(spec)}}) {
    write_text_file(path, text);
    std::filesystem::permissions(path, std::filesystem::perms::owner_exec | std::filesystem::perms::group_exec |
                                           std::filesystem::perms::others_exec,
                                 std::filesystem::perm_options::add);
  }
  std::filesystem::remove(slurm_dir(spec) / "exit_code");  // the merge job writes this night's
  spdlog::info("job scripts: {} and {}", array_script_path(spec).string(), merge_script_path(spec).string());
  if (o.slurm.dry_run) {
    // Runnable as printed: the merge takes the array's id from the first command.
    std::string merge;
    for (const std::string& a : sbatch_merge_argv(spec, "ARRAY_ID"))
      merge += (merge.empty() ? "" : " ") + (a == "--dependency=afterany:ARRAY_ID" ? "--dependency=afterany:\"${array%%;*}\""
                                                                                  : shell_quote(a));
    fmt::print("array=$({}) &&\n  {}\n", command_line(sbatch_array_argv(spec)), merge);
    return 0;
  }
  const std::optional<std::filesystem::path> sbatch = find_on_path("sbatch");
  if (!sbatch) {
    std::fprintf(stderr,
                 "giharness: nightly --slurm: sbatch not found on PATH (install Slurm's client, e.g. Debian's "
                 "slurm-client, or use --slurm-dry-run to only write the scripts to %s)\n",
                 slurm_dir(spec).c_str());
    return 3;
  }
  const std::optional<std::string> array_id =
      submit(sbatch_array_argv(spec), *sbatch, slurm_dir(spec) / "sbatch-array.out");
  if (!array_id) return 3;
  const std::optional<std::string> merge_id =
      submit(sbatch_merge_argv(spec, *array_id), *sbatch, slurm_dir(spec) / "sbatch-merge.out");
  if (!merge_id) {
    std::fprintf(stderr,
                 "giharness: nightly --slurm: the array (job %s) is submitted but its merge is not: cancel it with "
                 "`scancel %s`, or merge its shards yourself with `%s`\n",
                 array_id->c_str(), array_id->c_str(), merge_script_path(spec).c_str());
    return 3;
  }
  write_text_file(slurm_dir(spec) / "jobs.json",
                  nlohmann::json{{"array", *array_id}, {"merge", *merge_id}, {"tasks", spec.tasks}}.dump(2) + "\n");
  spdlog::info("submitted: array job {} ({} tasks), merge job {} after it; logs in {}; the report will be {}",
               *array_id, spec.tasks, *merge_id, slurm_dir(spec).string(), (spec.out_dir / "report.html").string());
  fmt::print("{} {}\n", *array_id, *merge_id);
  return 0;
}

}  // namespace gi
