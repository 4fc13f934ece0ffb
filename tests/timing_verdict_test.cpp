// The nightly's timing verdicts (reports/timing_verdict.h), in
// process on synthetic timing sets: an unchanged pass stays quiet, a slowed
// one is flagged, a machine 2x faster or slower of the same class compares
// through the calibration kernel, a load on part of the run is absorbed, and
// timing never touches the correctness verdicts (JUnit, exit code).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/errors.h"
#include "reports/junit.h"
#include "reports/suite_report.h"
#include "reports/timing_report.h"
#include "reports/timing_verdict.h"

namespace gi {
namespace {

// Per-frame times of one pass: a level, frame-to-frame noise of `jitter`
// (lognormal), an AR(1) drift so neighbouring frames correlate as they do on
// a shared machine, and a rare descheduled frame at 3x.
std::vector<double> noisy_series(double level, std::size_t n, std::uint64_t seed, double jitter = 0.08) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> v;
  double drift = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    drift = 0.7 * drift + 0.3 * jitter * normal(rng);
    double x = level * std::exp(drift + jitter * normal(rng));
    if (uniform(rng) < 0.03) x *= 3.0;
    v.push_back(x);
  }
  return v;
}

TimingSamples samples_in_ms(std::map<std::string, std::vector<double>> series) {
  TimingSamples t;
  t.unit = "ms";
  t.series = std::move(series);
  return t;
}

// Malformed baseline samples: an InputError that names the JSON path.
void expect_bad_samples(const nlohmann::json& bad, const std::string& path) {
  try {
    TimingSamples::from_json(bad, "b.json");
    FAIL() << "malformed samples were read (" << path << ")";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

const SeriesVerdict& series(const TimingComparison& c, const std::string& name) {
  for (const SeriesVerdict& s : c.series)
    if (s.name == name) return s;
  throw std::runtime_error("no series " + name);
}

// A summary.json's frame records as a run on a CPU device writes them:
// `speed` scales every time (a machine `speed`x slower), `load(frame)` a
// stretch of frames, `pass_factor` one pass only (a real regression).
nlohmann::json summary_of_run(std::uint64_t seed, double speed, double pass_factor = 1.0,
                              double (*load)(std::size_t) = nullptr, bool calibrated = true) {
  const std::size_t n = 60;
  const std::vector<double> calibration = noisy_series(0.30, n, seed * 7 + 1, 0.05);
  const std::vector<double> tiles = noisy_series(2.0, n, seed * 7 + 2);
  const std::vector<double> shade = noisy_series(6.0, n, seed * 7 + 3);
  const std::vector<double> output = noisy_series(0.4, n, seed * 7 + 4);
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t f = 0; f < n; ++f) {
    const double k = speed * (load ? load(f) : 1.0);
    nlohmann::json rec = {{"frame", f},
                          {"pass_ms",
                           {{"light_tiles", tiles[f] * k * pass_factor},
                            {"di_spatial_shade", shade[f] * k},
                            {"frame_output", output[f] * k}}}};
    if (f == 0) rec["pass_ms"]["light_tiles"] = 80.0;  // frame 0 compiles the pipeline inside its timestamps
    if (f + 1 == n) rec["pass_ms"]["state_hash"] = 0.02;
    if (calibrated) rec["calibration_ms"] = calibration[f] * k;
    frames.push_back(rec);
  }
  return {{"frames", frames}};
}

TEST(TimingVerdict, SamplesAreCalibratedPerFrameWithoutFrameZeroOrTheStateHash) {
  const TimingSamples t = timing_samples(summary_of_run(1, 1.0));
  EXPECT_EQ(t.unit, "calibration");
  EXPECT_NEAR(t.calibration_ms, 0.30, 0.05);
  EXPECT_EQ(t.series.count("state_hash"), 0u);
  ASSERT_EQ(t.series.at("light_tiles").size(), 59u);
  for (double x : t.series.at("light_tiles")) EXPECT_LT(x, 80.0 / 0.2);  // frame 0's compile is not in
  // The pipeline's total leaves the observation passes out.
  const double total = t.series.at(kPipelineTotal)[10];
  EXPECT_NEAR(total, t.series.at("light_tiles")[10] + t.series.at("di_spatial_shade")[10], 1e-9 * total);
  const TimingSamples ms = timing_samples(summary_of_run(1, 1.0, 1.0, nullptr, /*calibrated=*/false));
  EXPECT_EQ(ms.unit, "ms");
  EXPECT_NEAR(ms.series.at("di_spatial_shade")[0], summary_of_run(1, 1.0)["frames"][1]["pass_ms"]["di_spatial_shade"].get<double>(), 1e-12);
}

TEST(TimingVerdict, LongRunsAreSubsampledRegularly) {
  nlohmann::json frames = nlohmann::json::array();
  for (std::size_t f = 0; f < 301; ++f)
    frames.push_back({{"frame", f}, {"calibration_ms", 0.5}, {"pass_ms", {{"p", double(f)}}}});
  const TimingSamples t = timing_samples({{"frames", frames}});
  const std::vector<double>& p = t.series.at("p");
  ASSERT_EQ(p.size(), 60u);  // frames 1..300, every 5th
  EXPECT_DOUBLE_EQ(p[0], 1.0 / 0.5);
  EXPECT_DOUBLE_EQ(p[1], 6.0 / 0.5);
  EXPECT_LE(p.size(), kMaxTimingSamples);
}

TEST(TimingVerdict, AnUnchangedPassStaysQuietAndASlowedOneIsFlagged) {
  const TimingSamples base = samples_in_ms({{"p", noisy_series(2.0, 60, 11)}});
  const TimingComparison same = compare_timings(base, samples_in_ms({{"p", noisy_series(2.0, 60, 12)}}));
  EXPECT_EQ(same.verdict, "unchanged");
  EXPECT_LT(series(same, "p").low, 1.0);
  EXPECT_GT(series(same, "p").high, 1.0);
  const TimingComparison slow = compare_timings(base, samples_in_ms({{"p", noisy_series(3.0, 60, 13)}}));
  EXPECT_EQ(slow.verdict, "regressed");
  EXPECT_GT(series(slow, "p").low, 1.25);
  EXPECT_NEAR(series(slow, "p").ratio, 1.5, 0.15);
  // 10 % slower is below the minimum effect: reported as a ratio, never flagged.
  const TimingComparison bit_slower = compare_timings(base, samples_in_ms({{"p", noisy_series(2.2, 60, 14)}}));
  EXPECT_EQ(bit_slower.verdict, "unchanged");
  // Much faster is "improved", not a regression.
  const TimingComparison fast = compare_timings(base, samples_in_ms({{"p", noisy_series(1.0, 60, 15)}}));
  EXPECT_EQ(fast.verdict, "improved");
  EXPECT_EQ(fast.regressions(), 0u);
}

TEST(TimingVerdict, ATinyPassIsNotFlaggedForMicroseconds) {
  // 3x of 0.01 ms is 0.02 ms: below min_abs_ms, whatever the ratio says.
  const TimingSamples base = samples_in_ms({{"tiny", noisy_series(0.01, 60, 21)}});
  const TimingComparison c = compare_timings(base, samples_in_ms({{"tiny", noisy_series(0.03, 60, 22)}}));
  EXPECT_GT(series(c, "tiny").low, 1.25);
  EXPECT_EQ(series(c, "tiny").verdict, "unchanged");
}

// The false-alarm rate the header states: at a true ratio of 1 none of 100
// comparisons of independent runs flags; at exactly min_ratio, a few per
// cent at most (alpha is 0.1 %; the percentile bootstrap of a median on 60
// correlated frames is somewhat liberal, which this bounds); at 1.5x nearly
// every comparison flags.
TEST(TimingVerdict, FalseAlarmAndDetectionRatesOnIndependentRuns) {
  int null_flags = 0, edge_flags = 0, detected = 0;
  for (std::uint64_t k = 0; k < 100; ++k) {
    const TimingSamples base = samples_in_ms({{"p", noisy_series(2.0, 60, 1000 + k)}});
    null_flags += compare_timings(base, samples_in_ms({{"p", noisy_series(2.0, 60, 2000 + k)}})).regressions() > 0;
    edge_flags += compare_timings(base, samples_in_ms({{"p", noisy_series(2.5, 60, 3000 + k)}})).regressions() > 0;
    detected += compare_timings(base, samples_in_ms({{"p", noisy_series(3.0, 60, 4000 + k)}})).regressions() > 0;
  }
  EXPECT_EQ(null_flags, 0);
  EXPECT_LE(edge_flags, 5);
  EXPECT_GE(detected, 95);
}

TEST(TimingVerdict, TheSameInputsGiveTheSameInterval) {
  const std::vector<double> a = noisy_series(2.0, 60, 31), b = noisy_series(2.2, 60, 32);
  const RatioInterval x = median_ratio_interval(a, b, TimingPolicy{}, 99), y = median_ratio_interval(a, b, TimingPolicy{}, 99);
  EXPECT_EQ(x.low, y.low);
  EXPECT_EQ(x.high, y.high);
  EXPECT_LE(x.low, x.ratio);
  EXPECT_GE(x.high, x.ratio);
}

// The calibration test: a baseline taken on one machine and an
// unchanged tree on one of the same class 2x slower or 2x faster.
TEST(TimingVerdict, AMachineTwiceAsFastOrSlowCompares) {
  const TimingSamples base = timing_samples(summary_of_run(1, 1.0));
  for (double speed : {0.5, 2.0}) {
    const TimingComparison c = compare_timings(base, timing_samples(summary_of_run(2, speed)));
    EXPECT_EQ(c.verdict, "unchanged") << speed << " " << c.to_json().dump(1);
    EXPECT_NEAR(series(c, kPipelineTotal).ratio, 1.0, 0.1) << speed;
  }
  // Uncalibrated (times in ms), the same runs read as a 2x regression or
  // improvement: the calibration is what carries the baseline across.
  const TimingSamples base_ms = timing_samples(summary_of_run(1, 1.0, 1.0, nullptr, false));
  EXPECT_EQ(compare_timings(base_ms, timing_samples(summary_of_run(2, 2.0, 1.0, nullptr, false))).verdict, "regressed");
  EXPECT_EQ(compare_timings(base_ms, timing_samples(summary_of_run(2, 0.5, 1.0, nullptr, false))).verdict, "improved");
  // And on the slower machine a real 1.5x of one pass is still found, that pass only.
  const TimingComparison slowed = compare_timings(base, timing_samples(summary_of_run(3, 2.0, 1.5)));
  EXPECT_EQ(series(slowed, "light_tiles").verdict, "regressed");
  EXPECT_EQ(series(slowed, "di_spatial_shade").verdict, "unchanged");
}

// The calibration kernel's own median drifting (seen on lavapipe: up to
// ~30 % between runs of one scenario) moves every calibrated sample; with
// the pass's ms unchanged that is not a regression.
TEST(TimingVerdict, ACalibrationDriftAloneIsNotARegression) {
  const TimingSamples base = timing_samples(summary_of_run(1, 1.0));
  nlohmann::json drifted = summary_of_run(6, 1.0);
  for (nlohmann::json& f : drifted["frames"]) f["calibration_ms"] = f["calibration_ms"].get<double>() * 0.6;
  const TimingComparison c = compare_timings(base, timing_samples(drifted));
  EXPECT_NEAR(series(c, "di_spatial_shade").calibrated_ratio, 1.67, 0.2);  // calibrated, it reads 1.67x
  EXPECT_NEAR(series(c, "di_spatial_shade").ratio, 1.0, 0.15);  // against the other passes, unchanged
  EXPECT_NEAR(c.typical_ratio, 1.67, 0.2);
  EXPECT_EQ(c.verdict, "unchanged") << c.to_json().dump(1);
}

// A concurrent build that loads the machine for a stretch of the run (frames
// 20-39 at 2.5x): the calibration of the frames around each frame absorbs it.
TEST(TimingVerdict, ALoadOnPartOfTheRunIsAbsorbed) {
  const TimingSamples base = timing_samples(summary_of_run(1, 1.0));
  auto build = [](std::size_t f) { return f >= 20 && f < 40 ? 2.5 : 1.0; };
  const TimingComparison c = compare_timings(base, timing_samples(summary_of_run(4, 1.0, 1.0, build)));
  EXPECT_EQ(c.verdict, "unchanged") << c.to_json().dump(1);
}

// A build beside the run on frames [first, last), as measured on the 2-core
// machine: the frame's threads wait for a CPU half the time they want it,
// its long pass reads 2.3x slower and a shorter one 1.6x, while the short
// calibration kernel hardly moves, so the calibration cannot absorb it.
// Every frame records its CPU schedule (quiet: 3 % waiting).
nlohmann::json with_cpu_load(nlohmann::json summary, std::size_t first, std::size_t last) {
  for (nlohmann::json& f : summary["frames"]) {
    const std::size_t frame = f["frame"];
    const bool loaded = frame >= first && frame < last;
    const double run_ms = 25.0, share = loaded ? 0.5 : 0.03;
    f["cpu_schedule"] = {{"run_ms", run_ms}, {"wait_ms", run_ms * share / (1.0 - share)}};
    if (!loaded) continue;
    f["pass_ms"]["di_spatial_shade"] = f["pass_ms"]["di_spatial_shade"].get<double>() * 2.3;
    f["pass_ms"]["light_tiles"] = f["pass_ms"]["light_tiles"].get<double>() * 1.6;
  }
  return summary;
}

TEST(TimingVerdict, AMachineLoadedAllRunIsNotJudgedAndSaysHowLoaded) {
  const TimingSamples base = timing_samples(with_cpu_load(summary_of_run(1, 1.0), 0, 0));
  EXPECT_TRUE(base.load_measured);
  EXPECT_EQ(base.loaded_frames, 0u);
  EXPECT_NEAR(base.median_wait_share, 0.03, 1e-9);
  const nlohmann::json loaded = with_cpu_load(summary_of_run(2, 1.0), 0, 60);
  // Without the frames' CPU schedule the load reads as a regression of the long pass...
  nlohmann::json unmeasured = loaded;
  for (nlohmann::json& f : unmeasured["frames"]) f.erase("cpu_schedule");
  EXPECT_EQ(compare_timings(base, timing_samples(unmeasured)).verdict, "regressed");
  // ... with it, the run is not judged, and the reason gives the figures.
  const TimingSamples run = timing_samples(loaded);
  EXPECT_EQ(run.unit, "calibration");  // no frame kept, and still the run's unit
  EXPECT_EQ(run.frames, 59u);
  EXPECT_EQ(run.loaded_frames, 59u);
  const TimingComparison c = compare_timings(base, run);
  EXPECT_EQ(c.verdict, "not_compared");
  EXPECT_EQ(c.regressions(), 0u);
  EXPECT_EQ(series(c, "di_spatial_shade").verdict, "loaded");
  EXPECT_NE(c.reason.find("59 of its 59 timed frames"), std::string::npos) << c.reason;
  EXPECT_NE(c.reason.find("median 50 %"), std::string::npos) << c.reason;
  EXPECT_EQ(c.to_json()["load"]["run"]["loaded_frames"], 59);
  // A baseline taken on a loaded machine is as unusable: said so.
  const TimingComparison other = compare_timings(run, base);
  EXPECT_EQ(other.verdict, "not_compared");
  EXPECT_NE(other.reason.find("during the baseline"), std::string::npos) << other.reason;
}

TEST(TimingVerdict, LoadedFramesAreLeftOutAndTheRestJudged) {
  const TimingSamples base = timing_samples(with_cpu_load(summary_of_run(1, 1.0), 0, 0));
  // A build over a third of the run: the quiet frames say "unchanged"...
  const TimingSamples run = timing_samples(with_cpu_load(summary_of_run(3, 1.0), 20, 40));
  EXPECT_EQ(run.loaded_frames, 20u);
  EXPECT_EQ(run.series.at("di_spatial_shade").size(), 39u);
  EXPECT_EQ(compare_timings(base, run).verdict, "unchanged");
  // ... and still find a real slowdown of one pass among them.
  const TimingComparison slowed = compare_timings(base, timing_samples(with_cpu_load(summary_of_run(4, 1.0, 1.5), 20, 40)));
  EXPECT_EQ(series(slowed, "light_tiles").verdict, "regressed");
  EXPECT_EQ(series(slowed, "di_spatial_shade").verdict, "unchanged");
}

TEST(TimingVerdict, TheLoadTravelsWithTheBaselineAndIsChecked) {
  const TimingSamples t = timing_samples(with_cpu_load(summary_of_run(1, 1.0), 10, 15));
  const TimingSamples back = TimingSamples::from_json(t.to_json(), "b.json");
  EXPECT_TRUE(back.load_measured);
  EXPECT_EQ(back.frames, t.frames);
  EXPECT_EQ(back.loaded_frames, 5u);
  EXPECT_NEAR(back.median_wait_share, t.median_wait_share, 1e-6);
  nlohmann::json bad = t.to_json();
  bad["load"]["frames"] = "many";
  expect_bad_samples(bad, "/timing_samples/load");
}

// A pass that runs at a speed of its own in each process (measured: an
// unchanged gbuffer_resolve at 0.81 ms in one run, 1.10 ms in the next): a
// baseline that kept another run's medians allows for that spread.
TEST(TimingVerdict, ABaselinesOtherRunsWidenWhatCountsAsASlowdown) {
  TimingSamples base = timing_samples(summary_of_run(1, 1.0));
  const TimingSamples slow_mode = timing_samples(summary_of_run(2, 1.0, 1.4));  // light_tiles 1.4x, every frame
  // One run as the baseline: the per-process 1.4x reads as a regression.
  EXPECT_EQ(series(compare_timings(base, slow_mode), "light_tiles").verdict, "regressed");
  // With a third run of the same tree in that mode kept beside it, it does not...
  base.other_runs.push_back(timing_samples(summary_of_run(3, 1.0)).medians());
  base.other_runs.push_back(timing_samples(summary_of_run(4, 1.0, 1.4)).medians());
  const TimingComparison c = compare_timings(base, slow_mode);
  EXPECT_EQ(series(c, "light_tiles").verdict, "unchanged") << c.to_json().dump(1);
  EXPECT_EQ(series(c, "light_tiles").baseline_runs, 3u);
  EXPECT_NEAR(series(c, "light_tiles").spread, 1.4, 0.15);
  EXPECT_NEAR(series(c, "di_spatial_shade").spread, 1.0, 0.15);
  // ... while 1.4x beyond the slowest of them is still found, that pass only.
  const TimingComparison slowed = compare_timings(base, timing_samples(summary_of_run(5, 1.0, 1.4 * 1.5)));
  EXPECT_EQ(series(slowed, "light_tiles").verdict, "regressed") << slowed.to_json().dump(1);
  EXPECT_EQ(series(slowed, "di_spatial_shade").verdict, "unchanged");
  // The kept runs travel with the baseline, and a malformed one is named.
  const TimingSamples back = TimingSamples::from_json(base.to_json(), "b.json");
  ASSERT_EQ(back.other_runs.size(), 2u);
  EXPECT_NEAR(back.other_runs[1].unit.at("light_tiles"), base.other_runs[1].unit.at("light_tiles"), 1e-3);
  EXPECT_NEAR(back.median_ms.at("light_tiles"), base.median_ms.at("light_tiles"), 1e-3);
  nlohmann::json bad = base.to_json();
  bad["other_runs"][1]["median_ms"]["light_tiles"] = -1;
  expect_bad_samples(bad, "/timing_samples/other_runs/1/median_ms/light_tiles");
}

// A regression a second run does not repeat (a per-process speed mode) is
// "unconfirmed", not a regression; one it repeats stays.
TEST(TimingVerdict, ARegressionMustRepeatInASecondRun) {
  const TimingSamples base = timing_samples(summary_of_run(1, 1.0));
  const TimingSamples slow = timing_samples(summary_of_run(2, 1.0, 2.0));
  TimingComparison once = compare_timings(base, slow);
  ASSERT_EQ(once.verdict, "regressed");
  confirm_timings(once, compare_timings(base, timing_samples(summary_of_run(3, 1.0))));
  EXPECT_EQ(series(once, "light_tiles").verdict, "unconfirmed");
  EXPECT_EQ(once.verdict, "unchanged");
  EXPECT_EQ(once.regressions(), 0u);
  EXPECT_EQ(once.to_json()["confirmed_by_second_run"], true);
  TimingComparison twice = compare_timings(base, slow);
  confirm_timings(twice, compare_timings(base, timing_samples(summary_of_run(4, 1.0, 2.0))));
  EXPECT_EQ(series(twice, "light_tiles").verdict, "regressed");
  EXPECT_EQ(twice.verdict, "regressed");
  // No second run to be had (it crashed): nothing repeats, nothing is claimed.
  TimingComparison lost = compare_timings(base, slow);
  confirm_timings(lost, TimingComparison{});
  EXPECT_EQ(lost.verdict, "unchanged");
}

TEST(TimingVerdict, MissingNewShortAndIncomparableSeriesAreSaidNotJudged) {
  const TimingSamples base = samples_in_ms({{"gone", noisy_series(1, 60, 1)}, {"short", {1, 1, 1}}, {"p", noisy_series(1, 60, 2)}});
  const TimingComparison c = compare_timings(
      base, samples_in_ms({{"short", {2, 2, 2}}, {"p", noisy_series(1, 60, 3)}, {"added", noisy_series(1, 60, 4)}}));
  EXPECT_EQ(series(c, "gone").verdict, "missing");
  EXPECT_EQ(series(c, "short").verdict, "too_few_samples");
  EXPECT_EQ(series(c, "added").verdict, "new");
  EXPECT_EQ(c.verdict, "unchanged");
  TimingSamples calibrated = base;
  calibrated.unit = "calibration";
  const TimingComparison other = compare_timings(calibrated, base);
  EXPECT_EQ(other.verdict, "not_compared");
  EXPECT_NE(other.reason.find("calibration"), std::string::npos);
  EXPECT_EQ(compare_timings(TimingSamples{}, base).verdict, "not_compared");
}

TEST(TimingVerdict, BaselineSamplesRoundTripAndBadOnesNameTheirPath) {
  const TimingSamples t = timing_samples(summary_of_run(5, 1.0));
  const TimingSamples back = TimingSamples::from_json(t.to_json(), "b.json");
  EXPECT_EQ(back.unit, t.unit);
  ASSERT_EQ(back.series.at("light_tiles").size(), t.series.at("light_tiles").size());
  EXPECT_NEAR(back.series.at("light_tiles")[3], t.series.at("light_tiles")[3], 1e-3 * t.series.at("light_tiles")[3]);  // four digits kept
  nlohmann::json bad = t.to_json();
  bad["series"]["light_tiles"][2] = "fast";
  expect_bad_samples(bad, "/timing_samples/series/light_tiles/2");
}

// Timing is its own verdict: a regressed timing leaves the row's verdict and
// the exit code alone, and fails JUnit's timing case only under
// --fail-on-timing, where it sets exit bit 4.
TEST(TimingVerdict, TimingNeverFailsTheNightUnlessAsked) {
  const TimingComparison slow = compare_timings(samples_in_ms({{"p", noisy_series(2.0, 60, 41)}}),
                                                samples_in_ms({{"p", noisy_series(4.0, 60, 42)}}));
  ASSERT_EQ(slow.verdict, "regressed");
  nlohmann::json suite = {{"suite", "s"},
                          {"scenarios", {{{"name", "a"}, {"file", "a.json"}, {"status", "complete"}, {"exit_code", 0},
                                          {"verdict", "pass"}, {"checks", nlohmann::json::array()},
                                          {"baseline_status", "compared"}, {"timing", slow.to_json()}}}}};
  EXPECT_EQ(suite_exit_code(suite), 0);
  std::string junit = junit_xml(suite);
  EXPECT_EQ(junit.find("<failure"), std::string::npos) << junit;
  EXPECT_NE(junit.find("name=\"timing\""), std::string::npos) << junit;
  EXPECT_NE(junit.find("p regressed"), std::string::npos) << junit;
  suite["fail_on_timing"] = true;
  EXPECT_EQ(suite_exit_code(suite), kTimingExitBit);
  junit = junit_xml(suite);
  EXPECT_NE(junit.find("<failure message=\"timing regressed (--fail-on-timing)"), std::string::npos) << junit;
  suite["scenarios"][0]["exit_code"] = 1;  // and a failed check besides
  EXPECT_EQ(suite_exit_code(suite), 1 | kTimingExitBit);
  EXPECT_EQ(timing_tally(suite)["scenarios_regressed"], nlohmann::json::array({"a"}));
}

TEST(TimingVerdict, HistoryKeepsTheNewestNightsOldestFirst) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "giharness-timing-history-test";
  std::filesystem::remove_all(dir);
  const TimingComparison c = compare_timings(samples_in_ms({{kPipelineTotal, noisy_series(2.0, 60, 51)}}),
                                             samples_in_ms({{kPipelineTotal, noisy_series(2.0, 60, 52)}}));
  const nlohmann::json suite = {{"scenarios", {{{"name", "a"}, {"verdict", "pass"}, {"timing", c.to_json()}}}}};
  for (const char* t : {"2026-12-01T00:00:00Z", "2026-12-03T00:00:00Z", "2026-12-02T00:00:00Z"})
    write_timing_history(dir, timing_history_entry(suite, t));
  const nlohmann::json h = read_timing_history(dir, 2);
  ASSERT_EQ(h.size(), 2u);
  EXPECT_EQ(h[0]["started"], "2026-12-02T00:00:00Z");
  EXPECT_EQ(h[1]["started"], "2026-12-03T00:00:00Z");
  EXPECT_NEAR(h[1]["scenarios"]["a"][kPipelineTotal]["ratio"].get<double>(), series(c, kPipelineTotal).ratio, 1e-12);
  const Plot trend = timing_trend_plot(h, timing_history_entry(suite, "tonight"));
  ASSERT_EQ(trend.series.size(), 1u);
  EXPECT_EQ(trend.series[0].points.size(), 3u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gi
