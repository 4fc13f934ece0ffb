#include "reports/timing_verdict.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "core/errors.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

double median_of(std::vector<double> v) { return percentile(std::move(v), 0.5); }

// FNV-1a: a seed per series that is the same on every platform (std::hash is not).
std::uint64_t seed_of(const std::string& name) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : name) h = (h ^ c) * 1099511628211ull;
  return h;
}

// One moving-block resample's median: blocks of `block` consecutive samples
// (wrapping at the end) from uniformly drawn starts, until n are drawn.
double resampled_median(const std::vector<double>& x, std::uint32_t block, std::mt19937_64& rng,
                        std::vector<double>& scratch) {
  const std::size_t n = x.size();
  scratch.clear();
  while (scratch.size() < n) {
    const std::size_t start = rng() % n;  // mt19937_64's output is specified; the modulo bias is 1e-17
    for (std::uint32_t k = 0; k < block && scratch.size() < n; ++k) scratch.push_back(x[(start + k) % n]);
  }
  const std::size_t mid = n / 2;
  std::nth_element(scratch.begin(), scratch.begin() + mid, scratch.end());
  if (n % 2 == 1) return scratch[mid];
  const double upper = scratch[mid];
  return 0.5 * (upper + *std::max_element(scratch.begin(), scratch.begin() + mid));
}

nlohmann::json medians_json(const std::map<std::string, double>& m) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, x] : m) j[name] = std::stod(fmt::format("{:.4g}", x));
  return j;
}

// {"series": number >= 0, ...} at `path`.
std::map<std::string, double> medians_from_json(const nlohmann::json& j, const std::string& file, const std::string& path) {
  if (!j.is_object()) throw InputError(file, path, "an object of series medians");
  std::map<std::string, double> m;
  for (const auto& [name, x] : j.items()) {
    if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < 0)
      throw InputError(file, path + "/" + name, "a finite number >= 0");
    m[name] = x;
  }
  return m;
}

// The typical change of a scenario's passes from `base` to `run`: the median
// over the passes they share (not the total) of their ratios of medians; NaN
// with fewer than kMinPassesForRelative.
double typical_ratio(const std::map<std::string, double>& run, const std::map<std::string, double>& base) {
  std::vector<double> ratios;
  for (const auto& [name, b] : base) {
    const auto it = run.find(name);
    if (name == kPipelineTotal || it == run.end() || b <= 0 || it->second <= 0) continue;
    ratios.push_back(it->second / b);
  }
  return ratios.size() >= kMinPassesForRelative ? median_of(ratios) : std::nan("");
}

nlohmann::json load_json(const TimingSamples& t) {
  return {{"frames", t.frames}, {"loaded_frames", t.loaded_frames}, {"median_wait_share", json_figure(t.median_wait_share)},
          {"max_wait_share", json_figure(kMaxFrameWaitShare)}};
}

// The share of the CPU time the frame's threads wanted that they waited
// for; negative where the frame has no measurement.
double frame_wait_share(const nlohmann::json& f) {
  const nlohmann::json c = f.value("cpu_schedule", nlohmann::json());
  if (!c.is_object() || !c.contains("run_ms") || !c.contains("wait_ms") || !c["run_ms"].is_number() ||
      !c["wait_ms"].is_number())
    return -1.0;
  const double run = c["run_ms"], wait = c["wait_ms"];
  return run + wait > 0 ? wait / (run + wait) : 0.0;
}

// The scenario's verdict from its series': regressed, else improved, else
// unchanged when any series was judged.
void settle_verdict(TimingComparison& c) {
  auto any = [&](std::initializer_list<const char*> verdicts) {
    return std::any_of(c.series.begin(), c.series.end(), [&](const SeriesVerdict& v) {
      return std::any_of(verdicts.begin(), verdicts.end(), [&](const char* x) { return v.verdict == x; });
    });
  };
  c.verdict = any({"regressed"}) ? "regressed"
              : any({"improved"}) ? "improved"
              : any({"unchanged", "unconfirmed"}) ? "unchanged"
                                                  : "not_compared";
}

}  // namespace

nlohmann::json TimingSamples::to_json() const {
  nlohmann::json s = nlohmann::json::object();
  for (const auto& [name, v] : series) {
    nlohmann::json a = nlohmann::json::array();
    // Four significant digits: the samples vary by percents, and a
    // baseline of 40 scenarios stays small.
    for (double x : v) a.push_back(std::stod(fmt::format("{:.4g}", x)));
    s[name] = a;
  }
  nlohmann::json j = {{"unit", unit}, {"calibration_ms", json_figure(calibration_ms)}, {"series", s}};
  if (!median_ms.empty()) j["median_ms"] = medians_json(median_ms);
  if (load_measured) j["load"] = load_json(*this);
  if (!other_runs.empty()) {
    j["other_runs"] = nlohmann::json::array();
    for (const RunMedians& r : other_runs) j["other_runs"].push_back({{"median", medians_json(r.unit)}, {"median_ms", medians_json(r.ms)}});
  }
  return j;
}

TimingSamples TimingSamples::from_json(const nlohmann::json& j, const std::string& file) {
  if (!j.is_object() || !j.contains("unit") || !j["unit"].is_string() || !j.contains("series") ||
      !j["series"].is_object())
    throw InputError(file, "/timing_samples", "an object with string \"unit\" and object \"series\"");
  TimingSamples t;
  t.unit = j["unit"];
  if (t.unit != "ms" && t.unit != "calibration")
    throw InputError(file, "/timing_samples/unit", "\"ms\" or \"calibration\"");
  if (j.contains("calibration_ms") && j["calibration_ms"].is_number()) t.calibration_ms = j["calibration_ms"];
  if (j.contains("load")) {
    const nlohmann::json& l = j["load"];
    if (!l.is_object() || !l.contains("frames") || !l["frames"].is_number_unsigned() || !l.contains("loaded_frames") ||
        !l["loaded_frames"].is_number_unsigned() || !l.contains("median_wait_share") || !l["median_wait_share"].is_number())
      throw InputError(file, "/timing_samples/load",
                       "an object with counts \"frames\", \"loaded_frames\" and number \"median_wait_share\"");
    t.load_measured = true;
    t.frames = l["frames"];
    t.loaded_frames = l["loaded_frames"];
    t.median_wait_share = l["median_wait_share"];
  }
  if (j.contains("median_ms")) t.median_ms = medians_from_json(j["median_ms"], file, "/timing_samples/median_ms");
  if (j.contains("other_runs")) {
    if (!j["other_runs"].is_array()) throw InputError(file, "/timing_samples/other_runs", "an array of runs");
    for (std::size_t i = 0; i < j["other_runs"].size(); ++i) {
      const nlohmann::json& r = j["other_runs"][i];
      const std::string path = "/timing_samples/other_runs/" + std::to_string(i);
      if (!r.is_object() || !r.contains("median") || !r.contains("median_ms"))
        throw InputError(file, path, "an object with \"median\" and \"median_ms\"");
      t.other_runs.push_back({medians_from_json(r["median"], file, path + "/median"),
                              medians_from_json(r["median_ms"], file, path + "/median_ms")});
    }
  }
  for (const auto& [name, a] : j["series"].items()) {
    if (!a.is_array()) throw InputError(file, "/timing_samples/series/" + name, "an array of numbers");
    std::vector<double>& v = t.series[name];
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!a[i].is_number() || !std::isfinite(a[i].get<double>()) || a[i].get<double>() < 0)
        throw InputError(file, "/timing_samples/series/" + name + "/" + std::to_string(i), "a finite number >= 0");
      v.push_back(a[i]);
    }
  }
  return t;
}

TimingSamples timing_samples(const nlohmann::json& s) {
  TimingSamples out;
  const nlohmann::json frames = s.value("frames", nlohmann::json::array());
  // Frame 0 compiles pipelines inside its timestamps on lavapipe.
  std::vector<const nlohmann::json*> timed;
  for (const nlohmann::json& f : frames)
    if (f.is_object() && f.value("frame", 0u) > 0 && f.contains("pass_ms") && f["pass_ms"].is_object()) timed.push_back(&f);
  // Frames that waited too long for a CPU are out (see the header's "Load").
  std::vector<const nlohmann::json*> kept;
  std::vector<double> wait_shares;
  for (const nlohmann::json* f : timed) {
    const double share = frame_wait_share(*f);
    if (share >= 0) wait_shares.push_back(share);
    if (share > kMaxFrameWaitShare) ++out.loaded_frames;
    else kept.push_back(f);
  }
  out.frames = timed.size();
  out.load_measured = !wait_shares.empty();
  out.median_wait_share = out.load_measured ? median_of(wait_shares) : 0.0;
  // The unit is the run's, loaded frames or not: a run loaded all along is
  // "loaded", not "in another unit".
  auto has_calibration = [](const nlohmann::json* f) {
    const nlohmann::json c = f->value("calibration_ms", nlohmann::json());
    return c.is_number() && c.get<double>() > 0;
  };
  if (!timed.empty() && std::all_of(timed.begin(), timed.end(), has_calibration)) out.unit = "calibration";
  if (kept.empty()) return out;

  std::vector<double> calibration;
  for (const nlohmann::json* f : kept) {
    const nlohmann::json c = f->value("calibration_ms", nlohmann::json());
    if (c.is_number() && c.get<double>() > 0) calibration.push_back(c);
  }
  const bool calibrated = calibration.size() == kept.size();
  out.unit = calibrated ? "calibration" : "ms";
  out.calibration_ms = calibrated ? median_of(calibration) : 0.0;

  std::map<std::string, std::vector<double>> raw_ms;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    double scale = 1.0;
    if (calibrated) {
      const std::size_t half = kCalibrationWindow / 2;
      const std::size_t lo = i >= half ? i - half : 0, hi = std::min(calibration.size(), i + half + 1);
      scale = 1.0 / median_of(std::vector<double>(calibration.begin() + lo, calibration.begin() + hi));
    }
    double total = 0.0;
    bool any = false;
    for (const auto& [name, ms] : (*kept[i])["pass_ms"].items()) {
      if (!ms.is_number()) continue;
      // The state hash runs on the last frame (and hash-log frames) only:
      // a series of one or two frames says nothing about speed.
      if (name == "state_hash") continue;
      out.series[name].push_back(ms.get<double>() * scale);
      raw_ms[name].push_back(ms.get<double>());
      if (!observation_pass(name)) {
        total += ms.get<double>();
        any = true;
      }
    }
    if (any) {
      out.series[kPipelineTotal].push_back(total * scale);
      raw_ms[kPipelineTotal].push_back(total);
    }
  }
  for (auto& [name, v] : raw_ms) out.median_ms[name] = median_of(std::move(v));
  // A regular subsample of long runs: kMaxTimingSamples say as much about a
  // median as 300 frames do, and keep a baseline small (both sides alike).
  for (auto& [name, v] : out.series) {
    const std::size_t stride = (v.size() + kMaxTimingSamples - 1) / kMaxTimingSamples;
    if (stride <= 1) continue;
    std::vector<double> kept_samples;
    for (std::size_t i = 0; i < v.size(); i += stride) kept_samples.push_back(v[i]);
    v = std::move(kept_samples);
  }
  return out;
}

RunMedians TimingSamples::medians() const {
  RunMedians r;
  for (const auto& [name, v] : series) r.unit[name] = median_of(v);
  r.ms = median_ms;
  return r;
}

RatioInterval median_ratio_interval(const std::vector<double>& baseline, const std::vector<double>& measured,
                                    const TimingPolicy& policy, std::uint64_t seed) {
  RatioInterval r;
  const double b = median_of(baseline), m = median_of(measured);
  r.ratio = b > 0 ? m / b : 0.0;
  std::mt19937_64 rng(seed);
  std::vector<double> ratios, scratch;
  ratios.reserve(policy.resamples);
  for (std::uint32_t k = 0; k < policy.resamples; ++k) {
    const double bb = resampled_median(baseline, policy.block, rng, scratch);
    const double mm = resampled_median(measured, policy.block, rng, scratch);
    ratios.push_back(bb > 0 ? mm / bb : 0.0);
  }
  std::sort(ratios.begin(), ratios.end());
  const std::size_t lo = std::size_t(std::floor(policy.alpha * double(ratios.size())));
  const std::size_t hi = std::min(ratios.size() - 1, ratios.size() - 1 - lo);
  r.low = ratios[lo];
  r.high = ratios[hi];
  return r;
}

nlohmann::json SeriesVerdict::to_json() const {
  return {{"name", name},
          {"verdict", verdict},
          {"baseline_samples", baseline_samples},
          {"measured_samples", measured_samples},
          {"baseline_median", json_figure(baseline_median)},
          {"measured_median", json_figure(measured_median)},
          {"baseline_ms", json_figure(baseline_ms)},
          {"measured_ms", json_figure(measured_ms)},
          {"ratio", json_figure(ratio)},
          {"interval", {json_figure(low), json_figure(high)}},
          {"baseline_runs", baseline_runs},
          {"spread", json_figure(spread)},
          {"basis", basis},
          {"calibrated_ratio", json_figure(calibrated_ratio)}};
}

std::size_t TimingComparison::regressions() const {
  return std::size_t(std::count_if(series.begin(), series.end(), [](const SeriesVerdict& s) { return s.verdict == "regressed"; }));
}

nlohmann::json TimingComparison::to_json() const {
  nlohmann::json j = {{"verdict", verdict}, {"unit", unit}, {"interval_coverage", json_figure(interval)},
                      {"min_ratio", json_figure(min_ratio)}, {"min_abs_ms", json_figure(min_abs_ms)},
                      {"regressions", regressions()},
                      {"series", nlohmann::json::array()}};
  if (!reason.empty()) j["reason"] = reason;
  if (!load.is_null()) j["load"] = load;
  if (confirmed) j["confirmed_by_second_run"] = true;
  if (typical_ratio > 0) j["typical_ratio"] = json_figure(typical_ratio);
  for (const SeriesVerdict& s : series) j["series"].push_back(s.to_json());
  return j;
}

TimingComparison compare_timings(const TimingSamples& base, const TimingSamples& run, const TimingPolicy& policy) {
  TimingComparison out;
  out.unit = run.unit;
  out.interval = 1.0 - 2.0 * policy.alpha;
  out.min_ratio = policy.min_ratio;
  out.min_abs_ms = policy.min_abs_ms;
  if (base.load_measured) out.load["baseline"] = load_json(base);
  if (run.load_measured) out.load["run"] = load_json(run);
  // Too few quiet frames on a side: how loaded it was is the reason.
  auto loaded = [&](const TimingSamples& t) { return t.loaded(policy.min_samples); };
  auto load_reason = [](const char* side, const TimingSamples& t) {
    return fmt::format("the machine was loaded during the {}: {} of its {} timed frames waited for a CPU more than "
                       "{:.0f} % of the CPU time they wanted (median {:.0f} %; another job, or more of this "
                       "process's threads than CPUs)",
                       side, t.loaded_frames, t.frames, 100 * kMaxFrameWaitShare, 100 * t.median_wait_share);
  };
  if (loaded(run) || loaded(base)) {
    out.reason = loaded(run) ? load_reason("run", run) : load_reason("baseline", base);
    for (const auto& [name, b] : base.series) {
      SeriesVerdict v;
      v.name = name;
      v.verdict = "loaded";
      v.baseline_samples = b.size();
      const auto it = run.series.find(name);
      v.measured_samples = it == run.series.end() ? 0 : it->second.size();
      out.series.push_back(v);
    }
    return out;
  }
  if (base.series.empty() || run.series.empty()) {
    out.reason = base.series.empty() ? "the baseline has no timing samples" : "the run kept no timed frames";
    return out;
  }
  if (base.unit != run.unit) {
    out.reason = "the baseline's samples are in " + base.unit + ", the run's in " + run.unit;
    return out;
  }
  // A difference in the unit, stated in ms at each side's own calibration.
  auto to_ms = [](const TimingSamples& t, double v) { return t.unit == "calibration" ? v * t.calibration_ms : v; };
  // A series' median in ms: its raw frames' where recorded (baselines since
  // 2026-12-04), else its unit's median at the side's calibration.
  auto ms_of = [&](const TimingSamples& t, const std::string& name, double unit_median) {
    const auto it = t.median_ms.find(name);
    return it != t.median_ms.end() ? it->second : to_ms(t, unit_median);
  };
  // The typical change of the scenario's passes, this run's and each other
  // baseline run's against the baseline's own (see "Relative" in the header).
  const RunMedians base_medians = base.medians();
  const double typical = typical_ratio(run.medians().unit, base_medians.unit);
  std::vector<double> other_typical;
  for (const RunMedians& other : base.other_runs) other_typical.push_back(typical_ratio(other.unit, base_medians.unit));
  if (std::isfinite(typical)) out.typical_ratio = typical;
  for (const auto& [name, b] : base.series) {
    SeriesVerdict v;
    v.name = name;
    v.baseline_samples = b.size();
    v.baseline_median = median_of(b);
    v.baseline_ms = ms_of(base, name, v.baseline_median);
    const auto it = run.series.find(name);
    if (it == run.series.end()) {
      v.verdict = "missing";
      out.series.push_back(v);
      continue;
    }
    const std::vector<double>& m = it->second;
    v.measured_samples = m.size();
    v.measured_median = median_of(m);
    v.measured_ms = ms_of(run, name, v.measured_median);
    if (b.size() < policy.min_samples || m.size() < policy.min_samples || v.baseline_median <= 0) {
      v.verdict = "too_few_samples";
      v.ratio = v.baseline_median > 0 ? v.measured_median / v.baseline_median : 0.0;
      out.series.push_back(v);
      continue;
    }
    const RatioInterval r = median_ratio_interval(b, m, policy, seed_of(name));
    v.ratio = r.ratio;
    v.low = r.low;
    v.high = r.high;
    if (name != kPipelineTotal && std::isfinite(typical)) {
      // A pass, judged against the others: its interval over the typical
      // change, beyond the baseline runs' own relative spread.
      double rel_hi = 1.0, rel_lo = 1.0;
      v.baseline_runs = 1;
      for (std::size_t i = 0; i < base.other_runs.size(); ++i) {
        const auto u = base.other_runs[i].unit.find(name);
        if (u == base.other_runs[i].unit.end() || u->second <= 0 || !std::isfinite(other_typical[i])) continue;
        ++v.baseline_runs;
        const double rel = u->second / v.baseline_median / other_typical[i];
        rel_hi = std::max(rel_hi, rel);
        rel_lo = std::min(rel_lo, rel);
      }
      v.spread = rel_hi / rel_lo;
      v.basis = "relative";
      v.calibrated_ratio = r.ratio;
      v.ratio = r.ratio / typical;
      v.low = r.low / typical;
      v.high = r.high / typical;
      // At least min_abs_ms beyond the slowest (fastest) baseline run, at the run's speed.
      const double expected = v.baseline_median * typical;
      const bool enough_slower = to_ms(run, v.measured_median - expected * rel_hi) >= policy.min_abs_ms;
      const bool enough_faster = to_ms(run, expected * rel_lo - v.measured_median) >= policy.min_abs_ms;
      if (v.low > policy.min_ratio * rel_hi && enough_slower) v.verdict = "regressed";
      else if (v.high * policy.min_ratio < rel_lo && enough_faster) v.verdict = "improved";
      else v.verdict = "unchanged";
      out.series.push_back(v);
      continue;
    }
    // The baseline's runs, its own and the other ones kept with it: the
    // slowest and the fastest median of the series, in the unit and in ms.
    double unit_hi = v.baseline_median, unit_lo = v.baseline_median, ms_hi = v.baseline_ms, ms_lo = v.baseline_ms;
    v.baseline_runs = 1;
    for (const RunMedians& other : base.other_runs) {
      const auto u = other.unit.find(name), ms = other.ms.find(name);
      if (u == other.unit.end() || ms == other.ms.end() || u->second <= 0) continue;
      ++v.baseline_runs;
      unit_hi = std::max(unit_hi, u->second);
      unit_lo = std::min(unit_lo, u->second);
      ms_hi = std::max(ms_hi, ms->second);
      ms_lo = std::min(ms_lo, ms->second);
    }
    v.spread = unit_hi / unit_lo;
    const double slower_than = policy.min_ratio * unit_hi / v.baseline_median;  // on the interval's ratio scale
    const double faster_than = policy.min_ratio * v.baseline_median / unit_lo;
    // Calibrated, the slowdown must also show in ms (the medians at each
    // side's own speed): on lavapipe the calibration kernel's own median
    // moves by up to ~30 % between runs of one scenario, which alone would
    // read as a change of every pass; a real one moves both.
    const bool calibrated = run.unit == "calibration";
    const bool ms_slower = !calibrated || v.measured_ms > policy.min_ratio * ms_hi;
    const bool ms_faster = !calibrated || v.measured_ms * policy.min_ratio < ms_lo;
    // And by min_abs_ms at least, at the run's own speed: what this machine lost now.
    const bool enough_slower = to_ms(run, v.measured_median - unit_hi) >= policy.min_abs_ms;
    const bool enough_faster = to_ms(run, unit_lo - v.measured_median) >= policy.min_abs_ms;
    if (r.low > slower_than && ms_slower && enough_slower) v.verdict = "regressed";
    else if (r.high < 1.0 / faster_than && ms_faster && enough_faster) v.verdict = "improved";
    else v.verdict = "unchanged";
    out.series.push_back(v);
  }
  for (const auto& [name, m] : run.series)
    if (!base.series.count(name)) {
      SeriesVerdict v;
      v.name = name;
      v.verdict = "new";
      v.measured_samples = m.size();
      v.measured_median = median_of(m);
      v.measured_ms = ms_of(run, name, v.measured_median);
      out.series.push_back(v);
    }
  settle_verdict(out);
  if (out.verdict == "not_compared") out.reason = fmt::format("no series with {} timed frames on both sides", policy.min_samples);
  return out;
}

void confirm_timings(TimingComparison& first, const TimingComparison& second) {
  for (SeriesVerdict& v : first.series) {
    if (v.verdict != "regressed") continue;
    const auto again = std::find_if(second.series.begin(), second.series.end(),
                                    [&](const SeriesVerdict& s) { return s.name == v.name; });
    if (again == second.series.end() || again->verdict != "regressed") v.verdict = "unconfirmed";
  }
  first.confirmed = true;
  settle_verdict(first);
}

}  // namespace gi
