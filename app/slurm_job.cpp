#include "app/slurm_job.h"

#include <limits>
#include <regex>
#include <sstream>

#include <fmt/format.h>

#include "core/errors.h"

namespace gi {
namespace {

// What may go on an #SBATCH line: sbatch's own parser takes quotes as bash
// does but reads `\` as an escape even inside them, and a path in --output
// is a pattern (%a, %j, ...), so both are refused rather than half-escaped.
void check_sbatch_value(const std::string& flag, const std::string& value, bool is_pattern) {
  if (value.find('\n') != std::string::npos || value.find('\\') != std::string::npos)
    throw InputError(flag, "", "expected no newline and no backslash (it goes on an #SBATCH line), got \"" + value + "\"");
  if (is_pattern && value.find('%') != std::string::npos)
    throw InputError(flag, "", "expected a path without '%' (sbatch reads it in the log name as a pattern), got \"" +
                                   value + "\"");
}

void check_no_newline(const std::string& flag, const std::string& value) {
  if (value.find('\n') != std::string::npos || value.find('\r') != std::string::npos)
    throw InputError(flag, "", "expected no newline (it goes into a job script), got \"" + value + "\"");
}

void check_token(const std::string& flag, const std::string& value) {
  check_sbatch_value(flag, value, false);
  if (value.find_first_of(" \t'\"#") != std::string::npos)
    throw InputError(flag, "", "expected one word without spaces, quotes or '#', got \"" + value + "\"");
}

std::string sbatch_line(const std::string& option) { return "#SBATCH " + shell_quote(option) + "\n"; }

// #SBATCH lines both jobs share: where they run and what they are charged to.
std::string common_sbatch_lines(const SlurmJobSpec& s) {
  std::string text;
  if (!s.partition.empty()) text += sbatch_line("--partition=" + s.partition);
  if (!s.time_limit.empty()) text += sbatch_line("--time=" + s.time_limit);
  for (const std::string& a : s.sbatch_args) text += sbatch_line(a);
  return text;
}

std::string junit_of(const SlurmJobSpec& s) { return (s.junit.empty() ? s.out_dir / "junit.xml" : s.junit).string(); }

}  // namespace

std::filesystem::path slurm_dir(const SlurmJobSpec& spec) { return spec.out_dir / "slurm"; }
std::filesystem::path array_script_path(const SlurmJobSpec& spec) { return slurm_dir(spec) / "nightly-array.sh"; }
std::filesystem::path merge_script_path(const SlurmJobSpec& spec) { return slurm_dir(spec) / "merge.sh"; }

std::string shell_quote(const std::string& text) {
  std::string q = "'";
  for (char c : text) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

std::optional<long> slurm_time_seconds(const std::string& text) {
  if (text == "UNLIMITED" || text == "INFINITE" || text == "unlimited" || text == "infinite")
    return std::numeric_limits<long>::max();
  std::smatch m;
  auto n = [&](int k) { return m[k].matched ? std::stol(m[k].str()) : 0L; };
  try {
    // sbatch(1) --time: "minutes", "minutes:seconds", "hours:minutes:seconds".
    if (std::regex_match(text, m, std::regex(R"((\d{1,9}))"))) return n(1) * 60;
    if (std::regex_match(text, m, std::regex(R"((\d{1,9}):(\d{1,2}))"))) return n(1) * 60 + n(2);
    if (std::regex_match(text, m, std::regex(R"((\d{1,9}):(\d{1,2}):(\d{1,2}))")))
      return n(1) * 3600 + n(2) * 60 + n(3);
    // "days-hours", "days-hours:minutes", "days-hours:minutes:seconds".
    if (std::regex_match(text, m, std::regex(R"((\d{1,6})-(\d{1,2})(?::(\d{1,2}))?(?::(\d{1,2}))?)")))
      return n(1) * 86400 + n(2) * 3600 + n(3) * 60 + n(4);
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

void check_spec(const SlurmJobSpec& s) {
  if (s.tasks < 1) throw InputError("--slurm", "", fmt::format("expected at least 1 task, got {}", s.tasks));
  for (const auto& [flag, path] :
       {std::pair{"giharness", s.giharness}, {"--suite", s.suite}, {"--baseline", s.baseline_dir}, {"--junit", s.junit}})
    check_no_newline(flag, path.string());
  check_sbatch_value("--out", s.out_dir.string(), true);
  if (!s.partition.empty()) check_token("--slurm-partition", s.partition);
  if (!s.gres.empty()) check_token("--slurm-gres", s.gres);
  if (!s.time_limit.empty() && !slurm_time_seconds(s.time_limit))
    throw InputError("--slurm-time", "",
                     "expected Slurm's time format (M, M:S, H:M:S, D-H, D-H:M, D-H:M:S or UNLIMITED), got \"" +
                         s.time_limit + "\"");
  if (s.cpus_per_task && *s.cpus_per_task < 1)
    throw InputError("--slurm-cpus-per-task", "", fmt::format("expected at least 1, got {}", *s.cpus_per_task));
  // sbatch --signal takes 0..65535 s.
  if (s.warn_seconds < 0 || s.warn_seconds > 65535)
    throw InputError("--slurm-warn-seconds", "", fmt::format("expected 0..65535 seconds, got {}", s.warn_seconds));
  if (s.warn_seconds > 0 && !s.time_limit.empty() && *slurm_time_seconds(s.time_limit) <= s.warn_seconds)
    throw InputError("--slurm-warn-seconds", "",
                     fmt::format("expected less than the time limit ({} = {} s), got {} s", s.time_limit,
                                 *slurm_time_seconds(s.time_limit), s.warn_seconds));
  if (s.max_requeues < 0)
    throw InputError("--slurm-max-requeues", "", fmt::format("expected 0 or more, got {}", s.max_requeues));
  for (const std::string& a : s.sbatch_args) {
    check_sbatch_value("--slurm-sbatch-arg", a, false);
    if (a.empty() || a[0] != '-')
      throw InputError("--slurm-sbatch-arg", "", "expected one sbatch option such as --account=gfx, got \"" + a + "\"");
  }
  for (const std::string& a : s.nightly_args) check_no_newline("nightly option", a);
}

std::string array_script(const SlurmJobSpec& s) {
  const std::string shard_log = (slurm_dir(s) / "shard-%a.log").string();
  std::string t;
  t += "#!/bin/bash\n";
  t += fmt::format("# giharness nightly as a Slurm job array, written by `giharness nightly --slurm {}`:\n", s.tasks);
  t += "# array task i runs shard i/N of the suite into <out>/shard-i. Submit with\n";
  t += "# sbatch, then the merge job (merge.sh) with --dependency=afterany:<this job's id>.\n";
  t += sbatch_line("--job-name=giharness-nightly");
  t += sbatch_line(fmt::format("--array=1-{}", s.tasks));
  // One log per task, appended to, so a requeued task's attempts follow each other.
  t += sbatch_line("--output=" + shard_log);
  t += sbatch_line("--open-mode=append");
  // Preemption and node failure requeue the task; it then resumes its shard.
  t += sbatch_line("--requeue");
  // USR1 to this shell (B:) before the time limit: the nightly is told to stop
  // after its scenario and the task requeues itself (Slurm requeues nothing that
  // ran out of time on its own).
  if (s.warn_seconds > 0) t += sbatch_line(fmt::format("--signal=B:USR1@{}", s.warn_seconds));
  t += common_sbatch_lines(s);
  if (s.cpus_per_task) t += sbatch_line(fmt::format("--cpus-per-task={}", *s.cpus_per_task));
  if (!s.gres.empty()) t += sbatch_line("--gres=" + s.gres);
  t += "set -uo pipefail\n\n";
  t += "giharness=" + shell_quote(s.giharness.string()) + "\n";
  t += "out=" + shell_quote(s.out_dir.string()) + "\n";
  t += fmt::format("tasks={}\n", s.tasks);
  t += fmt::format("max_requeues={}\n", s.max_requeues);
  t += "task=${SLURM_ARRAY_TASK_ID:?not a Slurm array task: submit this script with sbatch}\n";
  t += "restarts=${SLURM_RESTART_COUNT:-0}\n";
  t += "args=(nightly --suite " + shell_quote(s.suite.string()) + " --baseline " + shell_quote(s.baseline_dir.string()) +
       " --shard \"$task/$tasks\" --out \"$out/shard-$task\"";
  for (const std::string& a : s.nightly_args) t += " " + shell_quote(a);
  t += ")\n";
  t += "# A requeued attempt (SLURM_RESTART_COUNT > 0) keeps what the last one completed;\n";
  t += "# a first attempt starts afresh, as a plain nightly would, rather than keep an\n";
  t += "# older night's results in the same --out.\n";
  if (s.resume)
    t += "args+=(--resume)  # --resume at submission: every attempt resumes\n";
  else
    t += "if [ \"$restarts\" -gt 0 ]; then args+=(--resume); fi\n";
  t += "\n";
  t += "# The GPU Slurm gave this task (GRES), unless --device was given at submission.\n";
  t += "# SLURM_STEP_GPUS/SLURM_JOB_GPUS are the node's GPU indices; they equal\n";
  t += "# Vulkan's device index only when Vulkan enumerates the same GPUs in the\n";
  t += "# same order with no other device (lavapipe) before them. Where Slurm\n";
  t += "# constrains devices with cgroups, a task sees only its own GPUs: submit with\n";
  t += "# --device 0 instead. CUDA_VISIBLE_DEVICES is the last resort; a UUID there is skipped.\n";
  t += "device=" + (s.device ? std::to_string(*s.device) : std::string()) + "\n";
  t += "device_from=" + std::string(s.device ? "--device" : "") + "\n";
  t += "if [ -z \"$device\" ]; then\n";
  t += "  for var in SLURM_STEP_GPUS SLURM_JOB_GPUS CUDA_VISIBLE_DEVICES; do\n";
  t += "    ids=${!var:-}\n";
  t += "    [ -n \"$ids\" ] || continue\n";
  t += "    first=${ids%%,*}\n";
  t += "    case \"$first\" in\n";
  t += "      '' | *[!0-9]*) echo \"giharness-slurm: $var=$ids is not a device index; ignored\" >&2 ;;\n";
  t += "      *) device=$first; device_from=$var; break ;;\n";
  t += "    esac\n";
  t += "  done\n";
  t += "fi\n";
  t += "if [ -n \"$device\" ]; then args+=(--device \"$device\"); fi\n";
  t += "# lavapipe's threads: the CPUs Slurm allotted, not every core of the node\n";
  t += "# (this also names the device class, llvmpipe-<N>threads, the baselines use).\n";
  t += "if [ -n \"${SLURM_CPUS_PER_TASK:-}\" ]; then export LP_NUM_THREADS=$SLURM_CPUS_PER_TASK; fi\n";
  t += "\n";
  t += "echo \"giharness-slurm: task $task/$tasks (job ${SLURM_JOB_ID:-?}, attempt $((restarts + 1))) on $(hostname)," \
       " device ${device:-default}${device_from:+ from $device_from}, LP_NUM_THREADS=${LP_NUM_THREADS:-unset}," \
       " $(date -u +%FT%TZ)\"\n";
  t += "\n";
  t += "# The nightly runs in the background so this shell can take signals while it\n";
  t += "# runs. USR1 (time nearly up): pass SIGTERM on, so the nightly finishes its\n";
  t += "# scenario, writes its summary and exits, then requeue. TERM (scancel,\n";
  t += "# preemption, the time limit): Slurm sends it to every process of the job, the\n";
  t += "# nightly included, so it is not passed on (a second SIGTERM kills the nightly\n";
  t += "# at once); this shell only waits for the nightly to write its summary.\n";
  t += "pid= requeue=0 stop=\n";
  t += "trap 'requeue=1; stop=USR1; [ -n \"$pid\" ] && kill -TERM \"$pid\" 2>/dev/null' USR1\n";
  t += "trap 'stop=TERM' TERM INT\n";
  t += "\"$giharness\" \"${args[@]}\" &\n";
  t += "pid=$!\n";
  t += "if [ \"$stop\" = USR1 ]; then kill -TERM \"$pid\" 2>/dev/null; fi  # it came before $! was known\n";
  t += "while :; do\n";
  t += "  wait \"$pid\"\n";
  t += "  rc=$?\n";
  t += "  # Above 128 with the nightly still there: a trap ended the wait, not the nightly.\n";
  t += "  if [ \"$rc\" -gt 128 ] && kill -0 \"$pid\" 2>/dev/null; then continue; fi\n";
  t += "  break\n";
  t += "done\n";
  t += "echo \"giharness-slurm: task $task/$tasks: nightly exit $rc${stop:+ after SIG$stop}, $(date -u +%FT%TZ)\"\n";
  t += "if [ \"$requeue\" = 1 ] && grep -q '^  \"interrupted\": true' \"$out/shard-$task/summary.json\" 2>/dev/null; then\n";
  t += "  if [ \"$restarts\" -lt \"$max_requeues\" ]; then\n";
  t += "    echo \"giharness-slurm: task $task/$tasks: out of time, scenarios left:"
       " requeue $((restarts + 1))/$max_requeues\"\n";
  t += "    scontrol requeue \"$SLURM_JOB_ID\" && exit 0\n";
  t += "    echo \"giharness-slurm: task $task/$tasks: scontrol requeue failed\" >&2\n";
  t += "  else\n";
  t += "    echo \"giharness-slurm: task $task/$tasks: out of time again after $restarts requeues; giving up\" >&2\n";
  t += "  fi\n";
  t += "fi\n";
  t += "exit \"$rc\"\n";
  return t;
}

std::string merge_script(const SlurmJobSpec& s) {
  std::string t;
  t += "#!/bin/bash\n";
  t += fmt::format("# The merge job of `giharness nightly --slurm {}`: runs after every array task\n", s.tasks);
  t += "# ended, however it ended (afterany), and writes the one summary, JUnit and\n";
  t += "# report into <out>. A shard that left no summary.json is missing from the\n";
  t += "# report, named in this log, and makes the exit code 3.\n";
  t += sbatch_line("--job-name=giharness-nightly-merge");
  t += sbatch_line("--output=" + (slurm_dir(s) / "merge.log").string());
  t += sbatch_line("--open-mode=append");
  t += sbatch_line("--cpus-per-task=1");
  t += common_sbatch_lines(s);
  t += "set -uo pipefail\n\n";
  t += "giharness=" + shell_quote(s.giharness.string()) + "\n";
  t += "out=" + shell_quote(s.out_dir.string()) + "\n";
  t += "junit=" + shell_quote(junit_of(s)) + "\n";
  t += fmt::format("tasks={}\n", s.tasks);
  t += "shards=() missing=0\n";
  t += "for ((i = 1; i <= tasks; i++)); do\n";
  t += "  if [ -f \"$out/shard-$i/summary.json\" ]; then\n";
  t += "    shards+=(\"$out/shard-$i\")\n";
  t += "  else\n";
  t += "    echo \"giharness-slurm: shard $i/$tasks left no summary.json (see $out/slurm/shard-$i.log)\" >&2\n";
  t += "    missing=$((missing + 1))\n";
  t += "  fi\n";
  t += "done\n";
  t += "rc=3\n";
  t += "if [ ${#shards[@]} -gt 0 ]; then\n";
  std::string extra;
  for (const std::string& a : s.merge_args) extra += " " + shell_quote(a);
  t += "  \"$giharness\" merge \"${shards[@]}\" --out \"$out\" --junit \"$junit\"" + extra + "\n";
  t += "  rc=$?\n";
  t += "fi\n";
  t += "if [ \"$missing\" -gt 0 ]; then\n";
  t += "  echo \"giharness-slurm: $missing of $tasks shards missing from the report\" >&2\n";
  t += "  rc=3\n";
  t += "fi\n";
  t += "# The night's exit code, where a caller finds it without Slurm's accounting.\n";
  t += "echo \"$rc\" > \"$out/slurm/exit_code.tmp\" && mv \"$out/slurm/exit_code.tmp\" \"$out/slurm/exit_code\"\n";
  t += "echo \"giharness-slurm: merged ${#shards[@]} of $tasks shards: exit $rc, $(date -u +%FT%TZ)\"\n";
  t += "exit \"$rc\"\n";
  return t;
}

std::vector<std::string> sbatch_array_argv(const SlurmJobSpec& spec) {
  return {"sbatch", "--parsable", array_script_path(spec).string()};
}

std::vector<std::string> sbatch_merge_argv(const SlurmJobSpec& spec, const std::string& array_job_id) {
  return {"sbatch", "--parsable", "--dependency=afterany:" + array_job_id, merge_script_path(spec).string()};
}

std::optional<std::string> parsable_job_id(const std::string& sbatch_output) {
  // --parsable prints "<id>" or "<id>;<cluster>" on its own line, last.
  std::istringstream in(sbatch_output);
  std::string line;
  std::optional<std::string> id;
  const std::regex pattern(R"(\s*(\d+)(;\S+)?\s*)");
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_match(line, m, pattern)) id = m[1].str();
  }
  return id;
}

}  // namespace gi
