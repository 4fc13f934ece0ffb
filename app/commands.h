// The subcommands: options are bound to CLI11 here; each command's work lives
// in its own file (replay/run_scenario.cpp; here reference_command.cpp, nightly.cpp, …).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "reports/baseline_store.h"
#include "app/bench.h"
#include "app/inspect_command.h"
#include "replay/run_scenario.h"

namespace gi {

struct ReferenceCommandOptions {
  std::filesystem::path scenario;
  std::optional<std::uint32_t> spp;
  std::optional<std::uint32_t> frame;
  unsigned threads = 0;
  std::filesystem::path out_dir = "out/reference";
};

// `nightly --slurm N` (app/nightly_slurm.cpp): the suite as a Slurm job
// array of N shards, then a merge job; 0 runs the nightly here.
struct NightlySlurmOptions {
  int tasks = 0;
  std::string partition;
  std::string time_limit;            // per task, Slurm's format
  std::optional<int> cpus_per_task;  // also LP_NUM_THREADS of the task
  std::string gres;                  // e.g. gpu:1
  std::vector<std::string> sbatch_args;
  int warn_seconds = 300;  // before the time limit: stop after the scenario, requeue
  int max_requeues = 3;
  bool dry_run = false;    // write the scripts, print the sbatch commands, submit nothing
};

struct NightlyOptions {
  std::filesystem::path suite = "scenarios";
  std::filesystem::path out_dir = "out/nightly";
  std::optional<int> device;
  std::filesystem::path baseline_dir = "reports/baselines";  // <dir>/<device class>/<scenario>.json
  std::string shard;              // "i/n": every n-th scenario from the i-th (sorted by file name)
  std::filesystem::path junit;    // default <out>/junit.xml
  bool resume = false;            // keep completed scenarios of <out>/summary.json
  // Scenarios run at once, each in a process of its own. On lavapipe a
  // driver's compile is one thread, so 2 on 2 cores shorten a cold night by
  // a third; their passes then wait for a CPU, so above 1 no timing is
  // judged, no equal-time peers run and no baseline is written: time a
  // night with 1.
  std::size_t jobs = 1;
  bool update_baseline = false;   // write this run's figures as the baseline
  bool confirm_timing = true;     // a timing regression is confirmed by a second run of the scenario
  bool add_timing_run = false;    // add this run's timing medians to the baselines of bit-unchanged scenarios
  bool fail_on_change = false;    // a scenario whose bits changed against its exact baseline fails (exit 1)
  bool fail_on_timing = false;    // a timing regression sets exit bit 4 (reports/timing_report.h); else it only reports
  std::filesystem::path history_dir;  // keep this night's timing summary there and draw the trend of the last nights
  std::size_t history_nights = 14;
  double image_budget_mb = kDefaultImageBudgetMb;  // --update-baseline: the device class's baseline images stay within this
  double scenario_timeout = 3600.0;              // s of wall time per scenario, unless it sets timeout_seconds
  std::optional<std::uint64_t> memory_limit_mb;  // address-space limit of each scenario's process
  // --seeds N: each scenario at N seeds (core/seed_set.h), each in a process of
  // its own; seed 0 (the scenario's own) keeps today's layout and alone meets
  // the baseline; seed k > 0 goes to <out>/<name>/seed-<value>/.
  std::optional<std::uint32_t> seeds;
  NightlySlurmOptions slurm;
};

// The hidden `giharness nightly-scenario`: one scenario of a nightly, run in
// the child process the nightly started; its suite row goes to `row`.
struct NightlyScenarioOptions {
  std::filesystem::path scenario;
  std::filesystem::path out_dir;  // the suite's out dir (the scenario's results go to <out>/<name>)
  std::filesystem::path row;
  std::optional<int> device;
  std::optional<std::uint32_t> seeds;  // the nightly's --seeds: the row names its seed
  std::uint32_t seed_index = 0;        // k of the seed set; k > 0 runs into <out>/<name>/seed-<value>/
  std::size_t jobs = 1;                // the nightly's --jobs: above 1, no equal-time peers
};
int run_nightly_scenario(const NightlyScenarioOptions& options);  // app/nightly.cpp

// `run --seeds N` (app/run_seeds.cpp): the scenario at each seed of
// its set from options.seed (else the scenario's), into <out>/seed-<value>/,
// and the combined <out>/summary.json (reports/seed_verdicts.h). Exit 0 only
// when every check passed at every seed.
int run_seed_set(const Scenario& scenario, const RunOptions& options, std::uint32_t count);

struct BaselineUpdateOptions {
  std::filesystem::path from;     // a nightly's out dir
  std::filesystem::path baseline_dir = "reports/baselines";
  double image_budget_mb = kDefaultImageBudgetMb;  // the device class's baseline images stay within this (reports/baseline_store.h)
};

struct MergeOptions {
  std::vector<std::filesystem::path> inputs;  // shard out dirs
  std::filesystem::path out_dir = "out/nightly";
  std::filesystem::path junit;
  std::filesystem::path history_dir;  // as nightly --history: the merged night is the history's entry
  std::size_t history_nights = 14;
};

struct SweepOptions {
  std::filesystem::path scenario;
  std::vector<std::string> vary;  // "key=v1,v2,…", repeated: the cartesian product
  std::filesystem::path out_dir = "out/sweep";
  std::optional<int> device;
  std::optional<std::uint32_t> reference_spp;  // converged reference (default: the reference check's, else 1024)
  // Realtime points run two chains ("noise": true) and each row carries the
  // per-signal noise; ms/frame is then that of two chains.
  bool noise = false;
};

struct ReplayOptions {
  std::filesystem::path capture;          // a capture folder (manifest.json)
  std::optional<std::uint32_t> frames;    // run up to frame N − 1 (default: the capturing run's frame count)
  bool verify = false;                    // compare every frame's buffer hashes with the capturing run's
  std::filesystem::path out_dir = "out/replay";
  std::optional<int> device;              // default: the capturing run's
  std::vector<std::uint32_t> capture_frames;  // --capture: frames the replay captures (from the resumed frame on)
};

int run_replay_command(const ReplayOptions& options);           // app/replay_command.cpp
int run_baseline_update(const BaselineUpdateOptions& options);  // app/nightly.cpp
int run_merge(const MergeOptions& options);                     // app/merge.cpp
int run_sweep(const SweepOptions& options);                     // app/sweep.cpp

struct ClustersCommandOptions {
  std::filesystem::path input;  // scenario, glTF file, or "cliff[:key=value,...]"
  bool json = false;
  std::uint32_t max_triangles = 128;
};

struct SchemaOptions {
  std::filesystem::path out;  // empty: standard output
};

// app/schema_command.cpp
std::string scenario_schema_text();  // the schema as `giharness schema` prints it
int run_schema_command(const SchemaOptions& options);

int run_reference_command(const ReferenceCommandOptions& options);
int run_clusters_command(const ClustersCommandOptions& options);  // app/clusters_command.cpp
int run_nightly(const NightlyOptions& options);
int submit_slurm_nightly(const NightlyOptions& options);  // app/nightly_slurm.cpp
int list_devices_command();

// `giharness fidelity` (app/fidelity_command.cpp): the profiles' Bevy
// citations against a Bevy git checkout.
struct FidelityOptions {
  std::filesystem::path checkout;     // a Bevy clone or bare mirror
  std::vector<std::string> profiles;  // names or files; default: every profile of profile_dir()
  std::string upstream_ref;           // --ref: what changed upstream since each profile's bevy_ref
  bool record = false;                // write the fingerprints of unrecorded citations
  std::filesystem::path out;          // the report as JSON
};
int run_fidelity_command(const FidelityOptions& options);

class Commands {
 public:
  void add_to(CLI::App& app);
  int execute();

 private:
  CLI::App* run_ = nullptr;
  CLI::App* reference_ = nullptr;
  CLI::App* nightly_ = nullptr;
  CLI::App* devices_ = nullptr;
  CLI::App* baseline_ = nullptr;
  CLI::App* baseline_update_ = nullptr;
  CLI::App* merge_ = nullptr;
  CLI::App* sweep_ = nullptr;
  CLI::App* clusters_ = nullptr;
  CLI::App* bench_ = nullptr;
  CLI::App* inspect_ = nullptr;
  CLI::App* replay_ = nullptr;
  CLI::App* schema_ = nullptr;
  CLI::App* fidelity_ = nullptr;
  FidelityOptions fidelity_options_;
  CLI::App* nightly_scenario_ = nullptr;
  NightlyScenarioOptions nightly_scenario_options_;
  SchemaOptions schema_options_;
  ReplayOptions replay_options_;
  std::filesystem::path scenario_path_;
  RunOptions run_options_;
  std::string capture_list_;
  std::string replay_capture_list_;
  std::optional<std::uint32_t> run_seeds_;  // run --seeds N
  ReferenceCommandOptions reference_options_;
  NightlyOptions nightly_options_;
  BaselineUpdateOptions baseline_options_;
  MergeOptions merge_options_;
  SweepOptions sweep_options_;
  ClustersCommandOptions clusters_options_;
  BenchOptions bench_options_;
  InspectOptions inspect_options_;
};

}  // namespace gi
