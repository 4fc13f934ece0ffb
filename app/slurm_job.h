// The Slurm job scripts of `giharness nightly --slurm N`: an
// sbatch job array with one nightly shard per task, and a merge job that
// runs after the array. Pure functions of a spec, so the tests can read and
// execute the scripts without a scheduler; the submission is
// app/nightly_slurm.cpp.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gi {

struct SlurmJobSpec {
  // Absolute paths: the job runs wherever Slurm puts it, from any directory.
  std::filesystem::path giharness;  // the binary the tasks run
  std::filesystem::path suite;
  std::filesystem::path out_dir;     // shard i writes <out>/shard-i; the merge writes <out>
  std::filesystem::path baseline_dir;
  std::filesystem::path junit;       // the merged JUnit; empty: <out>/junit.xml
  int tasks = 1;                     // array size = shard count
  std::string partition;             // empty: the cluster's default
  std::string time_limit;            // per task, Slurm's format (e.g. 2:00:00); empty: the partition's
  std::optional<int> cpus_per_task;  // also lavapipe's LP_NUM_THREADS
  std::string gres;                  // e.g. gpu:1
  std::vector<std::string> sbatch_args;   // more #SBATCH options, verbatim (each one argument)
  std::vector<std::string> nightly_args;  // passed to every shard's nightly (--fail-on-change, ...)
  std::vector<std::string> merge_args;    // passed to the merge (--history DIR, ...)
  std::optional<int> device;              // --device given: every task uses it instead of Slurm's GPU
  bool resume = false;                    // resume the shards from the first attempt on (a resubmitted night)
  int warn_seconds = 300;  // USR1 this long before the time limit: stop, then requeue (0: none)
  int max_requeues = 3;    // self-requeues per task after a time-limit warning
};

// The files under <out>/slurm/.
std::filesystem::path slurm_dir(const SlurmJobSpec& spec);
std::filesystem::path array_script_path(const SlurmJobSpec& spec);
std::filesystem::path merge_script_path(const SlurmJobSpec& spec);

// Bash's single-quoted form of `text` ('it'\''s'); sbatch reads the same
// quoting in #SBATCH lines. Text with a newline is refused by check_spec.
std::string shell_quote(const std::string& text);

// Throws InputError naming the flag for what the scripts cannot carry: a
// newline anywhere, `%` or `\` in the out dir (sbatch's --output pattern
// would rewrite them), a malformed time limit, a warning not shorter than it.
void check_spec(const SlurmJobSpec& spec);

// Slurm's time formats (M, M:S, H:M:S, D-H, D-H:M, D-H:M:S) in seconds;
// nullopt when `text` is none of them.
std::optional<long> slurm_time_seconds(const std::string& text);

std::string array_script(const SlurmJobSpec& spec);
std::string merge_script(const SlurmJobSpec& spec);

// The submissions, as argv: the array, then the merge after every task of
// the array has ended, however it ended (afterany), so a failed shard still
// gets a report.
std::vector<std::string> sbatch_array_argv(const SlurmJobSpec& spec);
std::vector<std::string> sbatch_merge_argv(const SlurmJobSpec& spec, const std::string& array_job_id);

// The job id of `sbatch --parsable`'s output ("1234" or "1234;cluster",
// after any warning lines); nullopt when there is none.
std::optional<std::string> parsable_job_id(const std::string& sbatch_output);

}  // namespace gi
