#include "checks/reference_check.h"
#include "core/cache_root.h"
#include "core/json_reader.h"
#include "core/reference/reference_cache.h"
#include "checks/check_registry.h"
#include "checks/realtime_reference_check.h"
#include "core/run_options.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/exr_io.h"
#include "core/reference/reference_cache.h"
#include "reports/json_figures.h"

namespace gi {
namespace {

// validate_reference_params (at parse time) has range-checked every
// parameter; here they are only read.
double number_param(const CheckSpec& spec, const char* key, double fallback) {
  return spec.params.contains(key) ? spec.params[key].get<double>() : fallback;
}

// Per-pixel |x − y| luminance relative to y, so the map shows where the
// error is, not only where the image is bright.
Image error_map(const Image& x, const Image& y) {
  Image e(x.width, x.height);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const glm::vec3 d = glm::abs(x.pixels[i] - y.pixels[i]);
    e.pixels[i] = d / (glm::abs(y.pixels[i]) + glm::vec3(0.1f));
  }
  return e;
}

}  // namespace

ReferenceCheckParams reference_check_params(const CheckSpec& spec, const Scenario& scenario,
                                            std::uint32_t frame_count) {
  ReferenceCheckParams p;
  if (spec.params.contains("frames")) {
    const nlohmann::json& f = spec.params["frames"];
    if (!f.is_array() || f.empty())
      throw InputError(scenario.file.string(), spec.json_path + "/frames", "expected a non-empty array of frames");
    for (std::size_t i = 0; i < f.size(); ++i) {
      if (!f[i].is_number_unsigned() || f[i].get<std::uint64_t>() >= frame_count)
        throw InputError(scenario.file.string(), spec.json_path + "/frames/" + std::to_string(i),
                         fmt::format("expected a frame number below the frame count {}", frame_count));
      p.frames.push_back(f[i].get<std::uint32_t>());
    }
  } else {
    p.frames.push_back(frame_count - 1);
  }
  p.spp = static_cast<std::uint32_t>(number_param(spec, "spp", p.spp));
  p.relmse_noise_factor = number_param(spec, "relmse_noise_factor", p.relmse_noise_factor);
  p.energy_tolerance = number_param(spec, "energy_tolerance", p.energy_tolerance);
  p.relmse_tolerance = number_param(spec, "relmse_tolerance", p.relmse_tolerance);
  if (spec.params.contains("warmup_frames")) {
    const nlohmann::json& w = spec.params["warmup_frames"];
    if (scenario.mode != RenderMode::Realtime)
      throw InputError(scenario.file.string(), spec.json_path + "/warmup_frames",
                       "warmup_frames only in realtime mode (the reference mode's estimate has no warm-up)");
    const std::uint32_t first = *std::min_element(p.frames.begin(), p.frames.end());
    if (!w.is_number_unsigned() || w.get<std::uint64_t>() > first)
      throw InputError(scenario.file.string(), spec.json_path + "/warmup_frames",
                       fmt::format("expected a frame count no larger than the first compared frame {}", first));
    p.warmup_frames = w.get<std::uint32_t>();
  }
  if (spec.params.contains("chains")) {
    if (scenario.mode != RenderMode::Realtime)
      throw InputError(scenario.file.string(), spec.json_path + "/chains",
                       "chains only in realtime mode (the reference mode's halves are its own)");
    p.chains = spec.params["chains"].get<std::uint32_t>();
  }
  return p;
}

std::uint32_t scenario_reference_spp(const Scenario& scenario, std::uint32_t fallback) {
  const CheckSpec* spec = scenario.find_check("reference");
  return spec ? reference_check_params(*spec, scenario, scenario.frames).spp : fallback;
}

nlohmann::json without_reference_checks(const nlohmann::json& checks) {
  nlohmann::json kept = nlohmann::json::array();
  for (const nlohmann::json& c : checks)
    if (c.value("name", "") != "reference") kept.push_back(c);
  return kept;
}

ReferenceComparisons::ReferenceComparisons(ReferenceCheckParams params, std::uint32_t seed,
                                           std::filesystem::path cache_dir, std::filesystem::path out_dir)
    : params_(std::move(params)), seed_(seed), cache_dir_(std::move(cache_dir)), out_dir_(std::move(out_dir)) {}

bool ReferenceComparisons::wants(std::uint32_t frame) const {
  return std::find(params_.frames.begin(), params_.frames.end(), frame) != params_.frames.end();
}

ReferenceComparisons::Reference ReferenceComparisons::reference(const Scene& scene, std::uint32_t width,
                                                                std::uint32_t height, bool direct_only) const {
  ReferenceOptions options;
  options.width = width;
  options.height = height;
  options.spp = params_.spp;
  options.seed = seed_;
  options.direct_only = direct_only;
  Reference r;
  ReferenceResult result = cached_reference(scene, options, cache_dir_, &r.cached);
  r.mean = std::move(result.mean);
  r.half_a = std::move(result.half_a);
  r.half_b = std::move(result.half_b);
  r.seconds = result.seconds;
  return r;
}

void ReferenceComparisons::Tally::add(std::uint32_t frame, const ComparisonVerdict& verdict,
                                      const std::string& problem, CheckResult& r) {
  if (!verdict.passed && first_problem.empty()) first_problem = problem;
  if (!verdict.passed && !verdict.inconclusive) {
    if (!any_fail) r.first_failing_frame = frame;
    any_fail = true;
  }
  any_inconclusive = any_inconclusive || verdict.inconclusive;
}

Verdict ReferenceComparisons::Tally::verdict() const {
  return any_fail ? Verdict::fail : (any_inconclusive ? Verdict::inconclusive : Verdict::pass);
}

CheckResult ReferenceComparisons::start_result() const {
  CheckResult r;
  r.name = "reference";
  r.limits = {{"relmse_noise_factor", params_.relmse_noise_factor},
              {"energy_tolerance", params_.energy_tolerance},
              {"relmse_tolerance", params_.relmse_tolerance},
              {"reference_spp", params_.spp}};
  r.verdict = Verdict::inconclusive;
  r.message = "no frame was compared";
  return r;
}

nlohmann::json comparison_json(const Comparison& c) {
  return {{"relmse", json_figure(c.relmse)},
          {"noise_gpu", json_figure(c.noise_x)},
          {"noise_reference", json_figure(c.noise_y)},
          {"combined_noise", json_figure(c.combined_noise)},
          {"relmse_over_noise", json_figure(c.relmse_over_noise)},
          {"bias_relmse", json_figure(c.bias_relmse)},
          {"energy_ratio", json_figure(c.energy_ratio)},
          {"energy_ratio_sigma", json_figure(c.energy_ratio_sigma)},
          {"mean_abs_error", json_figure(c.mean_abs_error)},
          {"mean_rel_error", json_figure(c.mean_rel_error)},
          {"max_luminance_ratio", json_figure(c.max_luminance_ratio)},
          {"nonfinite_gpu", c.nonfinite_x}};
}

const char* verdict_name(const ComparisonVerdict& v) {
  return v.passed ? "pass" : (v.inconclusive ? "inconclusive" : "fail");
}

void ReferenceCheck::compare_frame(std::uint32_t frame, const Scene& scene, const GpuEstimate& gpu) {
  const Reference ref = reference(scene, gpu.mean.width, gpu.mean.height, false);
  FrameComparison c;
  c.frame = frame;
  c.comparison = compare(gpu.mean, gpu.half_a, gpu.half_b, ref.mean, ref.half_a, ref.half_b);
  c.verdict = c.comparison.judge(params_.relmse_noise_factor, params_.energy_tolerance, params_.relmse_tolerance);
  c.gpu_samples = gpu.samples;
  c.reference_spp = params_.spp;
  c.reference_seconds = ref.seconds;
  c.reference_cached = ref.cached;
  c.evidence = fmt::format("reference/frame_{:05}.exr", frame);
  const Image error = error_map(gpu.mean, ref.mean);
  write_exr(out_dir_ / c.evidence, {{"gpu", &gpu.mean}, {"embree", &ref.mean}, {"error", &error}});
  frames_.push_back(std::move(c));
}

CheckResult ReferenceCheck::result() const {
  CheckResult r = start_result();
  if (frames_.empty()) return r;
  Tally tally;
  nlohmann::json per_frame = nlohmann::json::array();
  for (const FrameComparison& f : frames_) {
    nlohmann::json j = comparison_json(f.comparison);
    j.update(nlohmann::json{{"frame", f.frame},
                            {"gpu_samples_per_pixel", f.gpu_samples},
                            {"reference_spp", f.reference_spp},
                            {"reference_seconds", json_figure(f.reference_seconds)},
                            {"reference_cached", f.reference_cached},
                            {"verdict", verdict_name(f.verdict)},
                            {"reason", f.verdict.reason}});
    per_frame.push_back(j);
    r.evidence.push_back(f.evidence);
    tally.add(f.frame, f.verdict, fmt::format("frame {}: {}", f.frame, f.verdict.reason), r);
  }
  r.figures["frames"] = per_frame;
  const Comparison& last = frames_.back().comparison;
  r.verdict = tally.verdict();
  r.message = r.verdict == Verdict::pass
                  ? fmt::format("frame {}: relMSE {:.3g} = {:.2f}x combined noise {:.3g}; energy ratio {:.4f}",
                                frames_.back().frame, last.relmse, last.relmse_over_noise, last.combined_noise,
                                last.energy_ratio)
                  : tally.first_problem;
  return r;
}


namespace {

// Types and ranges, at parse time; frames against the run's length when the
// check is made (--frames may shorten it).
void validate_reference_params(const CheckSpec& spec, const Scenario& scenario) {
  const JsonReader r(scenario.file.string());
  const nlohmann::json& j = spec.params;
  const std::string& path = spec.json_path;
  if (j.contains("frames")) {
    const nlohmann::json& f = r.array(j["frames"], path + "/frames", 1);
    for (std::size_t i = 0; i < f.size(); ++i) r.uint(f[i], JsonReader::at(path + "/frames", i), 0, kMaxFrames - 1);
  }
  if (j.contains("relmse_noise_factor")) r.number(j["relmse_noise_factor"], path + "/relmse_noise_factor", 0.0, 1e6);
  if (j.contains("energy_tolerance")) r.number(j["energy_tolerance"], path + "/energy_tolerance", 0.0, 1.0);
  if (j.contains("relmse_tolerance")) r.number(j["relmse_tolerance"], path + "/relmse_tolerance", 0.0, 1e6);
  // At least 2: the two half-sample images estimate the reference's noise.
  if (j.contains("spp")) r.uint(j["spp"], path + "/spp", 2, 1u << 24);
  if (j.contains("chains")) r.uint(j["chains"], path + "/chains", 2, kMaxChains);
}

// The reference mode: the accumulated mean and its two halves.
class ReferencePlugin final : public Check {
 public:
  explicit ReferencePlugin(const CheckContext& c)
      : check_(reference_check_params(c.spec, c.scenario, c.frames), c.seed, cache_root() / "reference",
               c.options.out_dir) {}
  CheckNeeds needs() const override {
    return {.reads = {FrameInput::output_image, FrameInput::reference_halves},
            .frames = std::set<std::uint32_t>(check_.params().frames.begin(), check_.params().frames.end())};
  }
  void observe(const FrameView& f, nlohmann::json&) override {
    check_.compare_frame(f.frame(), f.scene(),
                         GpuEstimate{f.output(), f.reference_half(0), f.reference_half(1), f.window_samples()});
  }
  CheckResult result() override { return check_.result(); }

 private:
  ReferenceCheck check_;
};

// The realtime mode: two independent chains, their frames and temporal means.
class RealtimeReferencePlugin final : public Check {
 public:
  explicit RealtimeReferencePlugin(const CheckContext& c)
      : check_(reference_check_params(c.spec, c.scenario, c.frames), c.seed, cache_root() / "reference",
               c.options.out_dir) {}
  CheckNeeds needs() const override {
    return {.reads = {FrameInput::chains},
            .frames = std::set<std::uint32_t>(check_.params().frames.begin(), check_.params().frames.end()),
            .chains = check_.params().chains,
            .warmup_frames = check_.params().warmup_frames};
  }
  void observe(const FrameView& f, nlohmann::json&) override {
    RealtimeEstimate estimate;
    for (std::uint32_t c = 0; c < check_.params().chains; ++c) {
      estimate.frames.push_back(f.chain_frame(c));
      estimate.means.push_back(f.chain_mean(c));
    }
    estimate.window_start = f.window_start();
    estimate.window_frames = f.chain_window_frames();
    estimate.full_gi = f.full_gi();
    check_.compare_frame(f.frame(), f.scene(), estimate);
  }
  CheckResult result() override { return check_.result(); }

 private:
  RealtimeReferenceCheck check_;
};

// This check's parameters as scenarios/schema.json states them ($defs/check_reference,
// which `giharness schema` writes from here); the parser accepts exactly
// these keys.
constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "properties": {
    "name": {
      "const": "reference"
    },
    "frames": {
      "type": "array",
      "minItems": 1,
      "items": {
        "$ref": "#/$defs/frame"
      },
      "description": "Frames compared with the Embree reference."
    },
    "relmse_noise_factor": {
      "type": "number",
      "minimum": 0,
      "maximum": 1000000.0,
      "description": "relMSE limit as a multiple of the reference's own noise (e.g. 3.0)."
    },
    "energy_tolerance": {
      "type": "number",
      "minimum": 0,
      "maximum": 1,
      "description": "|energy ratio − 1| limit (e.g. 0.01)."
    },
    "relmse_tolerance": {
      "type": "number",
      "minimum": 0,
      "maximum": 1000000.0,
      "description": "Allowed bias in relMSE on top of the noise (default 0: the images must agree within noise)."
    },
    "warmup_frames": {
      "type": "integer",
      "minimum": 0,
      "description": "Realtime mode only: frames after the start of each static window left out of the temporal mean, so the check judges the steady state (e.g. a converged world cache), not the warm-up (default 0)."
    },
    "spp": {
      "type": "integer",
      "minimum": 2,
      "maximum": 16777216,
      "description": "Reference samples per pixel (at least 2: two half-sample images estimate its noise)."
    },
    "chains": {
      "type": "integer",
      "minimum": 2,
      "maximum": 16,
      "description": "Realtime mode only: independent chains, each a pipeline of its own that shares no state (default 2). Their mean is compared; its per-pixel noise is the chains' variance / K. With 2 the energy ratio's sigma sums the pixels' noise as if they were independent (fine where chains share no image-wide error); with K >= 3 it is the spread of the chains' mean luminances / sqrt(K) with K - 1 degrees of freedom, judged at the t quantile of the same two-sided 0.27 % false-alarm rate as 3 sigma of a normal. A GI scene whose world cache freezes a seed-dependent error for the whole run needs K >= 3 for an energy sigma that holds."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the relMSE and the energy ratio of the realtime temporal mean of K independent chains (or the "
    "reference mode's image) against the Embree path tracer",
    "relMSE: its expected value from noise, from the chains' (or the two halves') spread per pixel; "
    "energy: with K >= 3 chains the spread of their mean luminances / sqrt(K) (K - 1 degrees of "
    "freedom), with 2 chains or halves a sigma summed over pixels taken as independent, which is too "
    "small where the chains share an image-wide error (docs/statistics.md)",
    CheckModel::Basis::derived,
    0.0027,
    "energy: two-sided 0.27 % (3 sigma of a normal; Student's t with K - 1 degrees of freedom for K "
    ">= 3); relMSE: below relmse_noise_factor times its noise level plus relmse_tolerance"};

const CheckRegistration kRegistration{
    {"reference",
     kSchema,
     kModel,
     validate_reference_params},
    [](const CheckContext& c) -> std::unique_ptr<Check> {
      if (c.realtime) return std::make_unique<RealtimeReferencePlugin>(c);
      return std::make_unique<ReferencePlugin>(c);
    }};

}  // namespace

}  // namespace gi
