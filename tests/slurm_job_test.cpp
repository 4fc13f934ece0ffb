// `giharness nightly --slurm N`: the job scripts it writes. They
// are executed here with bash, fake SLURM_* variables and stubs of
// giharness, scontrol and sbatch on PATH that record their argv, so the
// device mapping, the resume and the requeue are tested as bash runs them,
// not by reading the text. .ci/slurm-nightly runs them under a real Slurm.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "app/slurm_job.h"
#include "tests/test_support.h"

namespace gi {
namespace {

std::vector<std::string> lines_of(const std::filesystem::path& file) {
  std::vector<std::string> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void write_executable(const std::filesystem::path& file, const std::string& text) {
  std::filesystem::create_directories(file.parent_path());
  std::ofstream(file) << text;
  std::filesystem::permissions(file, std::filesystem::perms::owner_all, std::filesystem::perm_options::add);
}

// A folder with spaces and a quote in its name, stubs that record each call
// in <dir>/calls/<tool>.argv (one argument a line) and the spec of a 4-task
// night there.
class SlurmScript : public ::testing::Test {
 protected:
  SlurmScript() : dir_("slurm-job"), root_(dir_.path() / "night's out dir") {
    bin_ = root_ / "bin dir";
    calls_ = root_ / "calls";
    std::filesystem::create_directories(calls_);
    // giharness: records argv and LP_NUM_THREADS; with STUB_HOLD it runs until
    // SIGTERM, then writes an interrupted summary into its --out, as the
    // nightly does, and exits 3.
    write_executable(bin_ / "giharness", R"(#!/bin/bash
calls=")" + calls_.string() + R"("
printf '%s\n' "$@" > "$calls/giharness.argv"
echo "${LP_NUM_THREADS-unset}" > "$calls/giharness.lp"
out=
while [ $# -gt 0 ]; do [ "$1" = --out ] && out=$2; shift; done
if [ -n "${STUB_HOLD:-}" ]; then
  trap 'echo TERM >> "$calls/giharness.signals"; mkdir -p "$out";
        printf "{\n  \"interrupted\": true\n}\n" > "$out/summary.json"; exit 3' TERM
  echo $$ > "$calls/giharness.started"
  while :; do sleep 0.05; done
fi
exit "${STUB_RC:-0}"
)");
    write_executable(bin_ / "scontrol", "#!/bin/bash\nprintf '%s\\n' \"$@\" > \"" + calls_.string() + "/scontrol.argv\"\n");
    spec_.giharness = bin_ / "giharness";
    spec_.suite = root_ / "suite";
    spec_.out_dir = root_ / "out";
    spec_.baseline_dir = root_ / "baselines";
    spec_.tasks = 4;
    spec_.nightly_args = {"--fail-on-change", "--scenario-timeout", "600"};
  }

  // Runs the array script as task `task` with `env` (assignments), only the
  // stubs' folder and the system's on PATH; the script's exit code.
  int run_task(int task, const std::string& env) {
    const std::filesystem::path script = root_ / "array.sh";
    std::ofstream(script) << array_script(spec_);
    const test::CommandResult r = test::run_command(
        "env -i PATH=" + shell_quote(bin_.string()) + ":/usr/bin:/bin SLURM_ARRAY_TASK_ID=" + std::to_string(task) +
        " SLURM_JOB_ID=777 " + env + " bash " + shell_quote(script.string()));
    output_ = r.output;
    return r.exit_code;
  }
  std::vector<std::string> argv() const { return lines_of(calls_ / "giharness.argv"); }
  // The value after `flag` in the stub's argv, or "" without it.
  std::string arg(const std::string& flag) const {
    const std::vector<std::string> a = argv();
    for (std::size_t i = 0; i + 1 < a.size(); ++i)
      if (a[i] == flag) return a[i + 1];
    return "";
  }
  bool has(const std::string& flag) const {
    for (const std::string& a : argv())
      if (a == flag) return true;
    return false;
  }

  test::TempDir dir_;
  std::filesystem::path root_, bin_, calls_;
  SlurmJobSpec spec_;
  std::string output_;
};

TEST_F(SlurmScript, IsAnArrayOfOneShardPerTaskThatRequeuesAndAppendsItsLog) {
  spec_.partition = "gpu";
  spec_.time_limit = "2:00:00";
  spec_.cpus_per_task = 8;
  spec_.gres = "gpu:1";
  spec_.sbatch_args = {"--account=gfx team"};
  const std::string s = array_script(spec_);
  EXPECT_TRUE(contains(s, "#SBATCH '--array=1-4'\n")) << s;
  EXPECT_TRUE(contains(s, "#SBATCH '--requeue'\n"));
  EXPECT_TRUE(contains(s, "#SBATCH '--open-mode=append'\n"));
  EXPECT_TRUE(contains(s, "#SBATCH '--signal=B:USR1@300'\n"));
  EXPECT_TRUE(contains(s, "#SBATCH '--partition=gpu'\n"));
  EXPECT_TRUE(contains(s, "#SBATCH '--time=2:00:00'\n"));
  EXPECT_TRUE(contains(s, "#SBATCH '--cpus-per-task=8'\n"));
  EXPECT_TRUE(contains(s, "#SBATCH '--gres=gpu:1'\n"));
  EXPECT_TRUE(contains(s, "#SBATCH '--account=gfx team'\n"));
  // One log per task, under a quoted absolute path (sbatch reads the quotes).
  EXPECT_TRUE(contains(s, "#SBATCH " + shell_quote("--output=" + (root_ / "out/slurm/shard-%a.log").string()) + "\n"))
      << s;
}

TEST_F(SlurmScript, TaskIRunsShardIOfNIntoItsOwnOutWithThePassedFlags) {
  ASSERT_EQ(run_task(3, ""), 0) << output_;
  ASSERT_FALSE(argv().empty()) << output_;
  EXPECT_EQ(argv()[0], "nightly");
  EXPECT_EQ(arg("--shard"), "3/4");
  EXPECT_EQ(arg("--out"), (root_ / "out/shard-3").string()) << "a path with spaces and a quote arrives whole";
  EXPECT_EQ(arg("--suite"), (root_ / "suite").string());
  EXPECT_EQ(arg("--baseline"), (root_ / "baselines").string());
  EXPECT_EQ(arg("--scenario-timeout"), "600");
  EXPECT_TRUE(has("--fail-on-change"));
  EXPECT_FALSE(has("--resume")) << "a first attempt starts afresh";
  EXPECT_FALSE(has("--device")) << "no GPU from Slurm: the nightly's default device (lavapipe)";
  EXPECT_EQ(lines_of(calls_ / "giharness.lp"), std::vector<std::string>{"unset"});
}

TEST_F(SlurmScript, ARequeuedTaskResumes) {
  ASSERT_EQ(run_task(2, "SLURM_RESTART_COUNT=1"), 0) << output_;
  EXPECT_TRUE(has("--resume"));
  EXPECT_EQ(arg("--out"), (root_ / "out/shard-2").string());
}

TEST_F(SlurmScript, ResumeAtSubmissionResumesEveryAttempt) {
  spec_.resume = true;
  ASSERT_EQ(run_task(1, ""), 0) << output_;
  EXPECT_TRUE(has("--resume"));
}

TEST_F(SlurmScript, TheNightlysExitCodeIsTheTasks) {
  EXPECT_EQ(run_task(1, "STUB_RC=1"), 1) << output_;
}

TEST_F(SlurmScript, TheDeviceIsTheFirstGpuSlurmGaveTheTask) {
  ASSERT_EQ(run_task(1, "SLURM_JOB_GPUS=3,5"), 0) << output_;
  EXPECT_EQ(arg("--device"), "3");
  // A step's own GPUs come first, then the job's, then CUDA_VISIBLE_DEVICES.
  ASSERT_EQ(run_task(1, "SLURM_STEP_GPUS=6 SLURM_JOB_GPUS=3,5 CUDA_VISIBLE_DEVICES=0"), 0) << output_;
  EXPECT_EQ(arg("--device"), "6");
  ASSERT_EQ(run_task(1, "CUDA_VISIBLE_DEVICES=2,1"), 0) << output_;
  EXPECT_EQ(arg("--device"), "2");
  // A UUID is no Vulkan index: the nightly keeps its default.
  ASSERT_EQ(run_task(1, "CUDA_VISIBLE_DEVICES=GPU-8f2c"), 0) << output_;
  EXPECT_FALSE(has("--device"));
  EXPECT_TRUE(contains(output_, "CUDA_VISIBLE_DEVICES=GPU-8f2c is not a device index")) << output_;
}

TEST_F(SlurmScript, DeviceGivenAtSubmissionWinsOverSlurms) {
  spec_.device = 0;
  ASSERT_EQ(run_task(2, "SLURM_JOB_GPUS=3 CUDA_VISIBLE_DEVICES=3"), 0) << output_;
  EXPECT_EQ(arg("--device"), "0");
  const std::vector<std::string> a = argv();
  EXPECT_EQ(std::count(a.begin(), a.end(), "--device"), 1);
}

TEST_F(SlurmScript, LavapipeThreadsAreTheCpusSlurmAllotted) {
  ASSERT_EQ(run_task(1, "SLURM_CPUS_PER_TASK=3 LP_NUM_THREADS=16"), 0) << output_;
  EXPECT_EQ(lines_of(calls_ / "giharness.lp"), std::vector<std::string>{"3"});
}

// The time-limit warning (USR1 to the batch shell): the nightly gets SIGTERM
// once, writes an interrupted summary, and the task requeues itself.
TEST_F(SlurmScript, TheTimeWarningStopsTheNightlyAndRequeuesTheTask) {
  const std::filesystem::path script = root_ / "array.sh";
  std::ofstream(script) << array_script(spec_);
  const std::string started = shell_quote((calls_ / "giharness.started").string());
  auto run = [&](const std::string& restarts) {
    std::filesystem::remove(calls_ / "scontrol.argv");
    std::filesystem::remove(calls_ / "giharness.signals");
    std::filesystem::remove(calls_ / "giharness.started");
    return test::run_command("env -i PATH=" + shell_quote(bin_.string()) +
                             ":/usr/bin:/bin SLURM_ARRAY_TASK_ID=2 SLURM_JOB_ID=777 SLURM_RESTART_COUNT=" + restarts +
                             " STUB_HOLD=1 bash " + shell_quote(script.string()) + " & p=$!; " +
                             "for i in $(seq 200); do [ -s " + started + " ] && break; sleep 0.05; done; " +
                             "kill -USR1 $p; wait $p; echo rc=$?");
  };
  const test::CommandResult r = run("0");
  EXPECT_TRUE(contains(r.output, "rc=0")) << r.output;
  EXPECT_EQ(lines_of(calls_ / "giharness.signals"), std::vector<std::string>{"TERM"}) << r.output;
  EXPECT_EQ(lines_of(calls_ / "scontrol.argv"), (std::vector<std::string>{"requeue", "777"})) << r.output;
  // Out of requeues: the task ends with the nightly's exit code, not requeued.
  const test::CommandResult last = run("3");
  EXPECT_TRUE(contains(last.output, "rc=3")) << last.output;
  EXPECT_FALSE(std::filesystem::exists(calls_ / "scontrol.argv")) << last.output;
  EXPECT_TRUE(contains(last.output, "giving up")) << last.output;
}

// SIGTERM (scancel, preemption, the time limit) reaches every process of a
// job from Slurm itself, so the script must not send the nightly a second
// one, which would kill it before it writes its summary.
TEST_F(SlurmScript, SigtermIsNotPassedOnAndTheTaskWaitsForTheSummary) {
  const std::filesystem::path script = root_ / "array.sh";
  std::ofstream(script) << array_script(spec_);
  const std::string started = shell_quote((calls_ / "giharness.started").string());
  const test::CommandResult r = test::run_command(
      "env -i PATH=" + shell_quote(bin_.string()) + ":/usr/bin:/bin SLURM_ARRAY_TASK_ID=1 SLURM_JOB_ID=5 " +
      "STUB_HOLD=1 bash " + shell_quote(script.string()) + " & p=$!; " + "for i in $(seq 200); do [ -s " + started +
      " ] && break; sleep 0.05; done; kill -TERM $p; sleep 0.3; kill -TERM $(cat " + started + "); wait $p; echo rc=$?");
  EXPECT_TRUE(contains(r.output, "rc=3")) << r.output;
  EXPECT_EQ(lines_of(calls_ / "giharness.signals"), std::vector<std::string>{"TERM"}) << r.output;
  EXPECT_FALSE(std::filesystem::exists(calls_ / "scontrol.argv")) << "cancelled or preempted: Slurm decides";
  EXPECT_TRUE(std::filesystem::exists(root_ / "out/shard-1/summary.json"));
}

TEST_F(SlurmScript, TheMergeRunsAfterAnyEndOfTheArrayOverTheShardsThatLeftASummary) {
  const std::vector<std::string> merge = sbatch_merge_argv(spec_, "4242");
  EXPECT_EQ(merge, (std::vector<std::string>{"sbatch", "--parsable", "--dependency=afterany:4242",
                                             (root_ / "out/slurm/merge.sh").string()}));
  EXPECT_EQ(sbatch_array_argv(spec_),
            (std::vector<std::string>{"sbatch", "--parsable", (root_ / "out/slurm/nightly-array.sh").string()}));

  for (int i : {1, 3, 4}) {
    std::filesystem::create_directories(root_ / "out" / ("shard-" + std::to_string(i)));
    std::ofstream(root_ / "out" / ("shard-" + std::to_string(i)) / "summary.json") << "{}";
  }
  std::filesystem::create_directories(root_ / "out/slurm");
  const std::filesystem::path script = root_ / "out/slurm/merge.sh";
  std::ofstream(script) << merge_script(spec_);
  auto run = [&](const std::string& env) {
    return test::run_command("env -i PATH=" + shell_quote(bin_.string()) + ":/usr/bin:/bin " + env + " bash " +
                             shell_quote(script.string()) + "; echo rc=$?");
  };
  const test::CommandResult missing = run("");
  const std::string out = (root_ / "out").string();
  EXPECT_EQ(argv(), (std::vector<std::string>{"merge", out + "/shard-1", out + "/shard-3", out + "/shard-4", "--out",
                                              out, "--junit", out + "/junit.xml"}))
      << missing.output;
  EXPECT_TRUE(contains(missing.output, "shard 2/4 left no summary.json")) << missing.output;
  EXPECT_TRUE(contains(missing.output, "rc=3")) << "a missing shard fails the night";
  EXPECT_EQ(lines_of(root_ / "out/slurm/exit_code"), std::vector<std::string>{"3"});

  std::filesystem::create_directories(root_ / "out/shard-2");
  std::ofstream(root_ / "out/shard-2/summary.json") << "{}";
  spec_.junit = root_ / "ci/junit.xml";
  std::ofstream(script) << merge_script(spec_);
  const test::CommandResult all = run("STUB_RC=1");
  EXPECT_TRUE(contains(all.output, "rc=1")) << all.output;  // merge's own code: a check failed
  EXPECT_EQ(arg("--junit"), (root_ / "ci/junit.xml").string());
  EXPECT_EQ(lines_of(root_ / "out/slurm/exit_code"), std::vector<std::string>{"1"});

  // The night's timing history is the merge's to keep (one entry per night, not per shard).
  spec_.merge_args = {"--history", (root_ / "history dir").string()};
  std::ofstream(script) << merge_script(spec_);
  run("");
  EXPECT_EQ(arg("--history"), (root_ / "history dir").string());
}

TEST(SlurmJob, ReadsTheJobIdOfParsableOutput) {
  EXPECT_EQ(parsable_job_id("1234\n"), "1234");
  EXPECT_EQ(parsable_job_id("sbatch: warning: something\n1234;cluster\n"), "1234");
  EXPECT_EQ(parsable_job_id("sbatch: error: Batch job submission failed\n"), std::nullopt);
}

TEST(SlurmJob, QuotesForBashAndSbatch) {
  EXPECT_EQ(shell_quote("/a b/c"), "'/a b/c'");
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
  const test::CommandResult r = test::run_command("printf '%s' " + shell_quote("$x `y` \"z\" it's #"));
  EXPECT_EQ(r.output, "$x `y` \"z\" it's #");
}

TEST(SlurmJob, TimeLimitsInSlurmsFormats) {
  EXPECT_EQ(slurm_time_seconds("30"), 1800);
  EXPECT_EQ(slurm_time_seconds("30:15"), 1815);
  EXPECT_EQ(slurm_time_seconds("2:00:00"), 7200);
  EXPECT_EQ(slurm_time_seconds("1-12"), 129600);
  EXPECT_EQ(slurm_time_seconds("1-0:30"), 88200);
  EXPECT_EQ(slurm_time_seconds("1-0:0:5"), 86405);
  EXPECT_EQ(slurm_time_seconds("2h"), std::nullopt);
  EXPECT_EQ(slurm_time_seconds(""), std::nullopt);
}

// Bad flags are InputError (exit 2) naming the flag.
TEST(SlurmJob, RefusesWhatTheScriptsCannotCarry) {
  SlurmJobSpec good;
  good.giharness = "/usr/bin/giharness";
  good.suite = "/s";
  good.out_dir = "/o";
  good.baseline_dir = "/b";
  EXPECT_NO_THROW(check_spec(good));
  auto message = [&](auto edit) {
    SlurmJobSpec s = good;
    edit(s);
    try {
      check_spec(s);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_TRUE(contains(message([](auto& s) { s.out_dir = "/o/50%"; }), "--out"));
  EXPECT_TRUE(contains(message([](auto& s) { s.out_dir = "/o\nx"; }), "--out"));
  EXPECT_TRUE(contains(message([](auto& s) { s.suite = "/s\nx"; }), "--suite"));
  EXPECT_TRUE(contains(message([](auto& s) { s.time_limit = "2h"; }), "--slurm-time"));
  EXPECT_TRUE(contains(message([](auto& s) { s.time_limit = "5"; }), "--slurm-warn-seconds"))
      << "300 s of warning in a 5-minute task";
  EXPECT_TRUE(contains(message([](auto& s) { s.partition = "a b"; }), "--slurm-partition"));
  EXPECT_TRUE(contains(message([](auto& s) { s.gres = "gpu:1\n"; }), "--slurm-gres"));
  EXPECT_TRUE(contains(message([](auto& s) { s.sbatch_args = {"account=x"}; }), "--slurm-sbatch-arg"));
  EXPECT_TRUE(contains(message([](auto& s) { s.sbatch_args = {"--comment=a\\b"}; }), "--slurm-sbatch-arg"));
  EXPECT_TRUE(contains(message([](auto& s) { s.warn_seconds = 70000; }), "--slurm-warn-seconds"));
  EXPECT_TRUE(contains(message([](auto& s) { s.tasks = 0; }), "--slurm"));
}

// The command itself: --slurm-dry-run writes the scripts, a fake sbatch
// takes the submission, and no sbatch at all is exit 3.
class SlurmCommand : public ::testing::Test {
 protected:
  SlurmCommand() : dir_("slurm-command"), out_(dir_.path() / "out dir") {}
  std::string args(const std::string& extra) const {
    return "nightly --suite " + shell_quote((test::source_dir() / "tests/data/suites/tiny").string()) + " --out " +
           shell_quote(out_.string()) + " " + extra;
  }
  test::TempDir dir_;
  std::filesystem::path out_;
};

TEST_F(SlurmCommand, DryRunWritesTheScriptsAndPrintsTheSubmission) {
  const test::CommandResult r = test::run_giharness(args("--slurm 3 --slurm-dry-run --device 1"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string array = test::read_text(out_ / "slurm/nightly-array.sh");
  EXPECT_TRUE(contains(array, "#SBATCH '--array=1-3'")) << array;
  EXPECT_TRUE(contains(array, "\ndevice=1\n")) << array;
  EXPECT_TRUE(contains(array, "giharness=" + shell_quote(std::filesystem::canonical(GIHARNESS_BINARY).string())));
  EXPECT_TRUE(std::filesystem::exists(out_ / "slurm/merge.sh"));
  EXPECT_TRUE(contains(r.output, "--dependency=afterany:\"${array%%;*}\"")) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out_ / "slurm/jobs.json"));
}

TEST_F(SlurmCommand, SubmitsTheArrayThenTheMergeAfterIt) {
  const std::filesystem::path bin = dir_.path() / "bin";
  write_executable(bin / "sbatch", "#!/bin/bash\nprintf '%s\\n' \"$@\" >> " +
                                       shell_quote((dir_.path() / "sbatch.argv").string()) +
                                       "\nn=$(grep -c -- --parsable " + shell_quote((dir_.path() / "sbatch.argv").string()) +
                                       ")\necho \"sbatch: warning: a stub\" >&2\necho \"$((4241 + n));cluster\"\n");
  const test::CommandResult r = test::run_giharness(args("--slurm 2"), "PATH=" + shell_quote(bin.string()) + ":$PATH");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(lines_of(dir_.path() / "sbatch.argv"),
            (std::vector<std::string>{"--parsable", (out_ / "slurm/nightly-array.sh").string(), "--parsable",
                                      "--dependency=afterany:4242", (out_ / "slurm/merge.sh").string()}));
  EXPECT_EQ(test::read_json(out_ / "slurm/jobs.json"), (nlohmann::json{{"array", "4242"}, {"merge", "4243"}, {"tasks", 2}}));
}

TEST_F(SlurmCommand, NoSbatchIsExit3AndBadFlagsAreExit2) {
  const test::CommandResult none = test::run_giharness(args("--slurm 2"), "PATH=/nonexistent");
  EXPECT_EQ(none.exit_code, 3) << none.output;
  EXPECT_TRUE(contains(none.output, "sbatch not found")) << none.output;
  for (const auto& [extra, flag] : std::vector<std::pair<std::string, std::string>>{
           {"--slurm 4 --slurm-dry-run", "--slurm"},  // 3 scenarios
           {"--slurm 2 --shard 1/2 --slurm-dry-run", "--shard"},
           {"--slurm 2 --update-baseline --slurm-dry-run", "--update-baseline"},
           {"--slurm 2 --slurm-time 2h --slurm-dry-run", "--slurm-time"},
           {"--slurm-partition gpu", "--slurm"},  // needs --slurm N
           {"--slurm 0", "--slurm"}}) {
    const test::CommandResult r = test::run_giharness(args(extra));
    EXPECT_EQ(r.exit_code, 2) << extra << "\n" << r.output;
    EXPECT_TRUE(contains(r.output, flag)) << extra << "\n" << r.output;
  }
}

TEST_F(SlurmCommand, ARefusedSubmissionIsExit3) {
  const std::filesystem::path bin = dir_.path() / "bin";
  write_executable(bin / "sbatch", "#!/bin/bash\necho 'sbatch: error: invalid partition specified: nope' >&2\nexit 1\n");
  const test::CommandResult r = test::run_giharness(args("--slurm 2 --slurm-partition nope"),
                                                    "PATH=" + shell_quote(bin.string()) + ":$PATH");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_TRUE(contains(r.output, "invalid partition specified")) << r.output;
}

}  // namespace
}  // namespace gi
