// Timing verdicts: is a pass slower than in its baseline, judged
// from per-frame samples with a stated false-alarm rate, separately from the
// correctness verdicts (reports/regression.h) so that a slow machine never
// hides a failed check and never fails a night on its own unless asked.
//
// Samples. Each frame record of a scenario's summary.json has every pass's
// GPU time (`pass_ms`). On a CPU device (lavapipe) the frame also timed the
// calibration kernel (gpu/passes/timing_calibration.h) just after its
// passes; a pass's sample is then its time over the calibration time of the
// frames around it (the median over a window of kCalibrationWindow frames),
// a number that stays put when the machine is 2x faster, or loaded by a
// build, for the whole run or for a stretch of it. On a GPU samples stay ms.
// The first frame is left out: lavapipe compiles a pipeline at its first
// dispatch, inside the timestamps.
//
// Load. On lavapipe the passes run on this process's threads, and a build
// beside the nightly makes them wait for a CPU: on the 2-core machine a
// frame's long passes then read 2-2.7x slower, its short ones and the
// calibration kernel (a short dispatch, seldom preempted) hardly at all, so
// no one factor per frame corrects every pass. The frame loop records how
// long the process's threads waited for a CPU during each frame
// (core/cpu_schedule.h); a frame whose threads waited more than
// kMaxFrameWaitShare of the CPU time they wanted is left out, and a run with
// too few frames left is not judged, saying how loaded it was. Quiet, the
// share is ~3 % (the driver's threads and the host's own); under a -j2 build
// ~50 %.
//
// Test. For each pass (and the pipeline's per-frame total), the statistic is
// the ratio of medians, run over baseline. Its interval comes from a moving
// block bootstrap of both sample sets (frames are correlated, so blocks of
// frames are resampled, not single frames), with a fixed seed per series, so
// the same inputs give the same verdict. A pass regressed when the lower end
// of the interval is above min_ratio (times the baseline's run-to-run spread,
// below) AND, calibrated, its median in ms is too (on lavapipe the calibration's own median moves by up to ~30 % between
// runs; a real slowdown moves both, a machine 2x slower only the ms, so a
// regression on a machine faster than the baseline's can be missed) AND it
// is at least min_abs_ms slower:
// under a true slowdown of exactly min_ratio, the chance of a flag is about
// alpha (one-sided), and an unchanged pass, whose ratio is near 1, is far
// below it. The minimum effect size matters as much as alpha: between-run
// variation that the calibration does not remove is not in the bootstrap's
// view, so a small, real-looking shift is never enough.
//
// Relative. The calibration carries a baseline across machines only roughly
// (its median drifts up to ~30 % between runs on the 2-core VM, and the
// machine's speed does as much), so a pass is judged against the scenario's
// other passes: its ratio and interval are divided by the typical ratio, the
// median over the passes of their ratios of medians (kMinPassesForRelative
// at least). A machine 2x faster, a drifting calibration, a slower memory
// move every pass alike and cancel; one pass that changed does not move the
// median. Measured on 30 quiet nights of 8 scenarios: unchanged passes read
// 0.85-1.22 (5th-95th percentile) relative, 0.72-1.44 calibrated; a 1.5x
// light_tiles read 1.25-2.05 relative, 1.09-2.08 calibrated. The blind spot:
// most passes slowing together reads as none; the pipeline's total, judged
// absolutely (calibrated, and in ms too), is what sees that.
//
// Run-to-run spread. Some passes run at a speed of their own in each process:
// on the 2-core VM an unchanged gbuffer_resolve took 0.81 ms in every frame
// of one run and 1.10 ms in every frame of the next (thread placement, memory
// layout), a shift no sample within one run can tell from a regression. A
// baseline may therefore keep the medians of other runs of the same tree
// (`nightly --add-timing-run`, up to kTimingRunsKept runs in all): a series
// then regressed only when it is min_ratio slower than the slowest of them,
// improved only when min_ratio faster than the fastest.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

inline constexpr std::size_t kCalibrationWindow = 17;  // frames: the one judged and eight either side
inline constexpr const char* kPipelineTotal = "pipeline_total";
inline constexpr std::size_t kMaxTimingSamples = 64;  // per series: longer runs are subsampled regularly
inline constexpr double kMaxFrameWaitShare = 0.15;     // a frame that waited more for a CPU: machine loaded
inline constexpr std::size_t kMinPassesForRelative = 3;  // passes in common to judge one against the others
inline constexpr std::size_t kTimingRunsKept = 8;      // a baseline's runs (its own and other_runs) bounding the spread

// One run's median per series, in the samples' unit and in ms.
struct RunMedians {
  std::map<std::string, double> unit, ms;
};

struct TimingSamples {
  // "calibration" (multiples of the calibration kernel's time) or "ms".
  std::string unit = "ms";
  // The run's median calibration time, to state a calibrated difference in
  // ms (NaN-free: 0 when the unit is ms).
  double calibration_ms = 0.0;
  // Per series (a pass, or kPipelineTotal: the frame's pass sum without the
  // observation passes), one sample per kept frame.
  std::map<std::string, std::vector<double>> series;
  // Per series, the median of its raw ms over the kept frames.
  std::map<std::string, double> median_ms;
  // Baselines only: the medians of other runs of the same tree, oldest first
  // (at most kTimingRunsKept - 1; see "Run-to-run spread").
  std::vector<RunMedians> other_runs;
  // The machine's load over the timed frames (none measured on a GPU, or in
  // runs recorded before it was): frames, those left out as loaded, and the
  // median share of the CPU time the process's threads waited for.
  bool load_measured = false;
  std::size_t frames = 0, loaded_frames = 0;
  double median_wait_share = 0.0;

  RunMedians medians() const;  // this run's
  // Too few frames left once the loaded ones are out (a run too short to
  // judge anyway is not said to be loaded).
  bool loaded(std::size_t min_samples) const {
    return loaded_frames > 0 && frames >= min_samples && frames - loaded_frames < min_samples;
  }
  nlohmann::json to_json() const;
  // InputError naming `file` and the JSON path when malformed.
  static TimingSamples from_json(const nlohmann::json& j, const std::string& file);
};

// From a scenario summary.json's frame records. Empty series when the run
// kept no frames (count-only scenarios).
TimingSamples timing_samples(const nlohmann::json& scenario_summary);

struct TimingPolicy {
  double min_ratio = 1.25;    // the smallest slowdown (or, inverted, speed-up) worth a verdict
  double alpha = 0.001;       // one-sided error rate of each end of the interval
  double min_abs_ms = 0.05;   // and at least this much slower or faster, in ms
  std::uint32_t resamples = 4000;
  std::uint32_t block = 4;    // frames per bootstrap block
  std::size_t min_samples = 8;  // fewer frames on either side: not judged
};

struct SeriesVerdict {
  std::string name;
  // "unchanged", "regressed", "improved", "too_few_samples", "loaded" (too
  // few frames left once the loaded ones are out), "unconfirmed" (regressed,
  // but not in a second run: confirm_timings), "new", "missing"
  std::string verdict;
  std::size_t baseline_samples = 0, measured_samples = 0;
  double baseline_median = 0.0, measured_median = 0.0;  // in the unit
  double baseline_ms = 0.0, measured_ms = 0.0;          // medians of the raw ms
  double ratio = 0.0, low = 0.0, high = 0.0;            // run / baseline, and its interval
  std::size_t baseline_runs = 0;  // runs of the baseline that had this series
  double spread = 1.0;            // their slowest median over their fastest (1: one run), on the judged scale
  // "relative" (a pass against the scenario's other passes: ratio and
  // interval are over the typical ratio) or "absolute" (the pipeline total,
  // or too few passes: in the samples' unit, with the ms rule).
  std::string basis = "absolute";
  double calibrated_ratio = 0.0;  // relative: the ratio in the samples' unit, before dividing
  nlohmann::json to_json() const;
};

struct TimingComparison {
  // "unchanged", "regressed", "improved" (none regressed, one faster),
  // "not_compared" (units differ: a baseline of another device type; no
  // samples on either side; no series long enough to judge, e.g. because
  // the machine was loaded: the reason says by how much).
  std::string verdict = "not_compared";
  std::string unit;
  std::string reason;  // why not compared
  double interval = 0.0;  // the interval's coverage, 1 - 2 alpha
  double min_ratio = 0.0;
  double min_abs_ms = 0.0;
  nlohmann::json load;  // {"baseline": {...}, "run": {...}} where measured (TimingSamples' load)
  double typical_ratio = 0.0;  // the median pass's ratio (0: too few passes to judge relatively)
  std::vector<SeriesVerdict> series;
  bool confirmed = false;  // confirm_timings ran on it: every "regressed" repeated in a second run
  std::size_t regressions() const;
  nlohmann::json to_json() const;
};

TimingComparison compare_timings(const TimingSamples& baseline, const TimingSamples& measured,
                                 const TimingPolicy& policy = {});

// A regression confirmed by a second run of the scenario (a process of its
// own): a series stays "regressed" only when `second` (the same baseline
// against the second run) says so too; otherwise "unconfirmed", which is not
// a regression. Rare per-process speed modes do not repeat; a real slowdown
// does. The scenario's verdict is then recomputed.
void confirm_timings(TimingComparison& first, const TimingComparison& second);

// The ratio of medians of two sample sets and its central 1 - 2 alpha
// interval by moving block bootstrap (exposed for its tests).
struct RatioInterval {
  double ratio = 0.0, low = 0.0, high = 0.0;
};
RatioInterval median_ratio_interval(const std::vector<double>& baseline, const std::vector<double>& measured,
                                    const TimingPolicy& policy, std::uint64_t seed);

}  // namespace gi
