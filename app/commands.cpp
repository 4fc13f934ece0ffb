#include "app/commands.h"

#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "core/scenario.h"
#include "core/seed_set.h"

namespace gi {
namespace {

std::vector<std::uint32_t> parse_frame_list(const std::string& text) {
  std::vector<std::uint32_t> frames;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    const std::string item = text.substr(start, end - start);
    try {
      std::size_t used = 0;
      const unsigned long v = std::stoul(item, &used);
      if (used != item.size() || v > 0xFFFFFFFFul) throw std::invalid_argument(item);
      frames.push_back(static_cast<std::uint32_t>(v));
    } catch (const std::exception&) {
      throw InputError("--capture", "", "expected a comma-separated list of frame numbers, got \"" + item + "\"");
    }
    start = end + 1;
  }
  return frames;
}

}  // namespace

void Commands::add_to(CLI::App& app) {
  run_ = app.add_subcommand("run", "run a scenario on the GPU pipeline");
  run_->add_option("scenario", scenario_path_, "scenario JSON file")->required();
  run_->add_option("--frames", run_options_.frames, "override the frame count");
  run_->add_option("--seed", run_options_.seed, "override the seed");
  run_->add_option("--seeds", run_seeds_,
                   "run at N seeds derived from the seed (--seed, else the scenario's; core/seed_set.h) into "
                   "<out>/seed-<value>/; <out>/summary.json: each check's verdict per seed, pass/fail/flaky")
      ->check(CLI::Range(1u, kMaxSeeds));
  run_->add_option("--device", run_options_.device, "Vulkan device index (see 'giharness devices')");
  run_->add_option("--backend", run_options_.backend, "tracing backend")
      ->check(CLI::IsMember({"auto", "rayquery", "bvh"}));
  run_->add_option("--capture", capture_list_, "frames to capture (EXR, .npy, manifest), e.g. 10,63");
  run_->add_option("--out", run_options_.out_dir, "output directory")->capture_default_str();
  run_->add_option("--profile", run_options_.profile, "profile name (scenarios/profiles) or file, instead of the scenario's");
  run_->add_option("--set", run_options_.sets, "override one profile value, key=value (repeatable)");
  run_->add_flag("--equal-time", run_options_.equal_time,
                 "summary.json \"equal_time\": the GPU and Embree path tracers at the realtime output's ms/frame, "
                 "and the per-signal noise, bias and ms (realtime runs with a reference check)");
  run_->add_flag("--hash-log", run_options_.record_hashes,
                 "hash every state buffer each frame into buffer_hashes.jsonl (on the GPU), as determinism does");

  reference_ = app.add_subcommand("reference", "render a scenario's frame with the Embree reference path tracer");
  reference_->add_option("scenario", reference_options_.scenario, "scenario JSON file")->required();
  reference_->add_option("--spp", reference_options_.spp, "samples per pixel (default: the reference check's, else 1024)");
  reference_->add_option("--frame", reference_options_.frame, "scene state after this frame's events (default: last)");
  reference_->add_option("--threads", reference_options_.threads, "CPU threads (0 = all)");
  reference_->add_option("--out", reference_options_.out_dir, "output directory")->capture_default_str();

  nightly_ = app.add_subcommand("nightly", "run every scenario of a suite and summarise");
  nightly_->add_option("--suite", nightly_options_.suite, "directory of scenario files")->capture_default_str();
  nightly_->add_option("--out", nightly_options_.out_dir, "output directory")->capture_default_str();
  nightly_->add_option("--device", nightly_options_.device, "Vulkan device index");
  nightly_->add_option("--baseline", nightly_options_.baseline_dir, "baseline root (a folder per device class)")
      ->capture_default_str();
  nightly_->add_option("--shard", nightly_options_.shard, "run shard i of n (i/n); merge with 'giharness merge'");
  nightly_->add_option("--junit", nightly_options_.junit, "JUnit XML file (default <out>/junit.xml)");
  nightly_->add_option("--jobs,-j", nightly_options_.jobs,
                       "scenarios run at once, each in a process of its own; above 1 no timing is judged, no "
                       "equal-time peers run and no baseline is written")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  nightly_->add_flag("--resume", nightly_options_.resume, "keep the completed scenarios of an interrupted run");
  nightly_->add_flag("--update-baseline", nightly_options_.update_baseline, "write this run's figures as baselines");
  nightly_->add_flag("!--no-timing-confirm", nightly_options_.confirm_timing,
                     "judge timing on one run: no second run of a scenario whose timing regressed");
  nightly_->add_flag("--add-timing-run", nightly_options_.add_timing_run,
                     "add this run's per-pass timing medians to the baselines of scenarios whose bits are unchanged "
                     "(their run-to-run spread; kept: the newest 7)");
  nightly_->add_flag("--fail-on-change", nightly_options_.fail_on_change,
                     "fail (exit 1) a scenario whose image or buffer hashes differ from its exact baseline");
  nightly_->add_flag("--fail-on-timing", nightly_options_.fail_on_timing,
                     "a timing regression sets exit bit 4 (exit 4, or 5 with a failed check); without it timing only reports");
  nightly_->add_option("--history", nightly_options_.history_dir,
                       "folder of past nights' timing summaries: this night's is added, the report draws the trend");
  nightly_->add_option("--history-nights", nightly_options_.history_nights, "nights the trend shows")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  nightly_->add_option("--image-budget-mb", nightly_options_.image_budget_mb,
                       "with --update-baseline: the largest baseline images are dropped above this total")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  nightly_->add_option("--scenario-timeout", nightly_options_.scenario_timeout,
                       "seconds of wall time per scenario (unless it sets timeout_seconds), then verdict timeout")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  nightly_->add_option("--memory-limit-mb", nightly_options_.memory_limit_mb,
                       "address-space limit of each scenario's process (off by default)")
      ->check(CLI::PositiveNumber);
  nightly_->add_option("--seeds", nightly_options_.seeds,
                       "run each scenario at N seeds derived from its own (core/seed_set.h); a check whose verdict "
                       "differs between seeds is flaky (a failure); the baseline comparison uses seed 0 alone")
      ->check(CLI::Range(1u, kMaxSeeds));
  // Slurm (app/nightly_slurm.cpp): the --slurm-* flags need --slurm N.
  NightlySlurmOptions& so = nightly_options_.slurm;
  CLI::Option* slurm = nightly_->add_option("--slurm", so.tasks,
                                            "submit the suite as a Slurm job array of N shards and a merge job "
                                            "after it (scripts in <out>/slurm/)")
                           ->check(CLI::PositiveNumber);
  nightly_->add_option("--slurm-partition", so.partition, "sbatch --partition")->needs(slurm);
  nightly_->add_option("--slurm-time", so.time_limit, "time limit per task, e.g. 2:00:00")->needs(slurm);
  nightly_->add_option("--slurm-cpus-per-task", so.cpus_per_task, "CPUs per task (and its LP_NUM_THREADS)")
      ->check(CLI::PositiveNumber)
      ->needs(slurm);
  nightly_->add_option("--slurm-gres", so.gres, "generic resources per task, e.g. gpu:1")->needs(slurm);
  nightly_->add_option("--slurm-sbatch-arg", so.sbatch_args,
                       "one more sbatch option for both jobs, written --slurm-sbatch-arg=--account=X (repeatable)")
      ->needs(slurm);
  nightly_->add_option("--slurm-warn-seconds", so.warn_seconds,
                       "seconds before the time limit at which a task stops after its scenario and requeues itself "
                       "(0: never)")
      ->capture_default_str()
      ->needs(slurm);
  nightly_->add_option("--slurm-max-requeues", so.max_requeues, "self-requeues per task after running out of time")
      ->capture_default_str()
      ->needs(slurm);
  nightly_->add_flag("--slurm-dry-run", so.dry_run, "write the job scripts and print the sbatch commands; submit nothing")
      ->needs(slurm);

  // One scenario of a nightly, in the process the nightly starts for it (hidden).
  nightly_scenario_ = app.add_subcommand("nightly-scenario", "")->group("");
  nightly_scenario_->add_option("scenario", nightly_scenario_options_.scenario)->required();
  nightly_scenario_->add_option("--out", nightly_scenario_options_.out_dir)->required();
  nightly_scenario_->add_option("--row", nightly_scenario_options_.row)->required();
  nightly_scenario_->add_option("--device", nightly_scenario_options_.device);
  nightly_scenario_->add_option("--seeds", nightly_scenario_options_.seeds);
  nightly_scenario_->add_option("--seed-index", nightly_scenario_options_.seed_index);
  nightly_scenario_->add_option("--jobs", nightly_scenario_options_.jobs);

  baseline_ = app.add_subcommand("baseline", "manage nightly baselines");
  baseline_update_ = baseline_->add_subcommand("update", "write a nightly's figures as the baselines of its device class");
  baseline_update_->add_option("--from", baseline_options_.from, "the nightly's out directory")->required();
  baseline_update_->add_option("--baseline", baseline_options_.baseline_dir, "baseline root")->capture_default_str();
  baseline_update_->add_option("--image-budget-mb", baseline_options_.image_budget_mb,
                               "the largest baseline images are dropped above this total")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  baseline_->require_subcommand(1);

  merge_ = app.add_subcommand("merge", "merge nightly shards into one suite with one report");
  merge_->add_option("inputs", merge_options_.inputs, "shard out directories")->required();
  merge_->add_option("--out", merge_options_.out_dir, "output directory")->capture_default_str();
  merge_->add_option("--junit", merge_options_.junit, "JUnit XML file (default <out>/junit.xml)");
  merge_->add_option("--history", merge_options_.history_dir,
                     "folder of past nights' timing summaries: the merged night's is added, the report draws the trend");
  merge_->add_option("--history-nights", merge_options_.history_nights, "nights the trend shows")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);

  sweep_ = app.add_subcommand("sweep", "vary parameters and report error against ms/frame, with Embree at equal time");
  sweep_->add_option("scenario", sweep_options_.scenario, "scenario JSON file")->required();
  sweep_->add_option("--vary", sweep_options_.vary, "key=v1,v2,... (repeatable; the cartesian product runs)")
      ->required();
  sweep_->add_option("--out", sweep_options_.out_dir, "output directory")->capture_default_str();
  sweep_->add_option("--device", sweep_options_.device, "Vulkan device index");
  sweep_->add_option("--reference-spp", sweep_options_.reference_spp, "spp of the converged Embree reference");
  sweep_->add_flag("--noise", sweep_options_.noise,
                   "realtime points run two chains and report each signal's per-frame noise (ms/frame is then two chains')");

  replay_ = app.add_subcommand("replay", "resume a capture bit for bit and continue the run");
  replay_->add_option("capture", replay_options_.capture, "capture folder (out/captures/frame_NNNNN)")->required();
  replay_->add_option("--frames", replay_options_.frames, "run up to frame N-1 (default: the capturing run's count)");
  replay_->add_flag("--verify", replay_options_.verify, "compare each frame's buffer hashes with the capturing run's");
  replay_->add_option("--out", replay_options_.out_dir, "output directory")->capture_default_str();
  replay_->add_option("--device", replay_options_.device, "Vulkan device index (default: the capturing run's)");
  replay_->add_option("--capture", replay_capture_list_,
                      "frames to capture, e.g. 3,7 (the replay runs from the frame after the capture's; inspect --against holds one against the capturing run's)");

  schema_ = app.add_subcommand("schema", "print the scenario JSON Schema, each check's parameters from its own file");
  schema_->add_option("--out", schema_options_.out, "write it to this file instead (atomically)");

  fidelity_ = app.add_subcommand(
      "fidelity", "hold every Bevy citation of the profiles to the lines it cites in a Bevy git checkout; exit 1 on drift");
  fidelity_->add_option("checkout", fidelity_options_.checkout, "a clone or bare mirror of Bevy's repository")
      ->required();
  fidelity_->add_option("--profile", fidelity_options_.profiles,
                        "a profile name or file (repeatable; default: every profile)");
  fidelity_->add_option("--ref", fidelity_options_.upstream_ref,
                        "also list what changed since each profile's release up to this ref (e.g. main): the "
                        "commits that touch a cited file, and the cited lines that moved, changed or went");
  fidelity_->add_flag("--record", fidelity_options_.record,
                      "write the fingerprint of every citation that has none, drop the stale ones (read the "
                      "cited lines first: the fingerprint says they are what the source claims)");
  fidelity_->add_option("--out", fidelity_options_.out, "write the report as JSON (atomically)");

  devices_ = app.add_subcommand("devices", "list Vulkan devices and their ray-tracing support");

  bench_ = add_bench_subcommand(app, bench_options_);  // app/bench.cpp
  inspect_ = add_inspect_subcommand(app, inspect_options_);  // app/inspect_command.cpp

  clusters_ = app.add_subcommand("clusters", "build the cluster DAG of a mesh or a scenario's meshes; per-level table");
  clusters_->add_option("input", clusters_options_.input,
                        "scenario (.json), glTF (.gltf/.glb) or mesh generator, e.g. cliff:triangles=1000000")
      ->required();
  clusters_->add_flag("--json", clusters_options_.json, "print JSON instead of the table");
  clusters_->add_option("--max-triangles", clusters_options_.max_triangles, "triangles per cluster (multiple of 4)")
      ->capture_default_str();
}

int Commands::execute() {
  if (run_->parsed()) {
    run_options_.capture = parse_frame_list(capture_list_);
    const Scenario scenario = load_scenario(scenario_path_);
    if (run_seeds_) return run_seed_set(scenario, run_options_, *run_seeds_);
    return run_scenario(scenario, run_options_).exit_code;
  }
  if (reference_->parsed()) return run_reference_command(reference_options_);
  if (replay_->parsed()) {
    replay_options_.capture_frames = parse_frame_list(replay_capture_list_);
    return run_replay_command(replay_options_);
  }
  if (nightly_->parsed()) return run_nightly(nightly_options_);
  if (nightly_scenario_->parsed()) return run_nightly_scenario(nightly_scenario_options_);
  if (devices_->parsed()) return list_devices_command();
  if (schema_->parsed()) return run_schema_command(schema_options_);
  if (fidelity_->parsed()) return run_fidelity_command(fidelity_options_);
  if (baseline_update_->parsed()) return run_baseline_update(baseline_options_);
  if (merge_->parsed()) return run_merge(merge_options_);
  if (sweep_->parsed()) return run_sweep(sweep_options_);
  if (clusters_->parsed()) return run_clusters_command(clusters_options_);
  if (bench_->parsed()) return run_bench(bench_options_);
  if (inspect_->parsed()) return run_inspect(inspect_options_);
  return 2;
}

}  // namespace gi
