// The light_leak check (Bevy #22252, #22348, #24332, #23968): light
// where the reference has shadow. Leaks through thin walls and into corners
// (world-cache cells keyed past a wall, cells larger than the gap they span,
// neighbours reused across an occluder) add light to regions the path
// tracer leaves dark, and a whole-image energy ratio hides them: the
// shadowed side is a small share of the image's energy, and the same bugs
// often darken the lit side.
//
// On each judged frame the realtime temporal mean of the chains is
// compared with the Embree full path tracer (the reference check's renders
// and cache) over the shadowed region only: the pixels whose reference
// luminance is below `shadow_fraction` of the reference's mean. Fails when
// the realtime energy there exceeds the reference's by more than
// `max_excess` plus the noise margin below.
//
// Statistical model: the region's energy ratio of the mean of K chains
// (pipelines that share no state, `chains`, default 8), against the path
// tracer. Its σ is the spread of the chains' region energies / √K with
// K − 1 degrees of freedom (metrics.h compare_chains): in a GI scene the
// world cache freezes a seed-dependent error over the whole region for the
// run, which a σ summed over pixels taken as independent misses (10× too
// small, docs/statistics.md). The limit is `max_excess` + q σ with q
// Student's t quantile at one-sided 0.135 % (3 σ of a normal): a fixed
// pipeline whose true excess is at most `max_excess` fails at most that
// often. `max_excess` is the pipeline's own excess in the scene, which a
// scenario takes from its measured mean over seeds, not one seed's figure.
#include <algorithm>

#include <fmt/format.h>

#include "core/cache_root.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/json_reader.h"
#include "checks/check_registry.h"
#include "checks/realtime_reference_check.h"
#include "core/run_options.h"
#include "reports/json_figures.h"

namespace gi {
namespace {

double lum(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Every image with the pixels outside `region` set to zero, so the shared
// comparison (core/metrics.h) measures the region alone.
Image masked(const Image& image, const std::vector<bool>& region) {
  Image m = image;
  for (std::size_t i = 0; i < m.size(); ++i)
    if (!region[i]) m.pixels[i] = glm::vec3(0.0f);
  return m;
}

struct LeakParams {
  ReferenceCheckParams reference;  // frames, spp, warmup_frames
  double shadow_fraction = 0.2;
  double max_excess = 0.1;
  std::uint32_t chains = 8;
};

LeakParams leak_params(const CheckContext& c) {
  if (!c.realtime || !c.gi)
    c.refuse("", "compares the full realtime image (\"mode\": \"realtime\", \"gi\": true) with the path tracer");
  LeakParams p;
  p.reference.spp = 256;
  p.reference.frames = {c.frames - 1};
  const JsonReader r(c.scenario.file.string());
  const nlohmann::json& j = c.spec.params;
  const std::string& at = c.spec.json_path;
  if (j.contains("frames")) {
    p.reference.frames.clear();
    const nlohmann::json& f = r.array(j["frames"], at + "/frames", 1);
    for (std::size_t i = 0; i < f.size(); ++i)
      p.reference.frames.push_back(r.uint(f[i], JsonReader::at(at + "/frames", i), 0, c.frames - 1));
  }
  if (j.contains("spp")) p.reference.spp = r.uint(j["spp"], at + "/spp", 2, 1u << 24);
  if (j.contains("warmup_frames")) p.reference.warmup_frames = r.uint(j["warmup_frames"], at + "/warmup_frames", 0, 1u << 24);
  if (j.contains("shadow_fraction"))
    p.shadow_fraction = (r.number(j["shadow_fraction"], at + "/shadow_fraction", 0.0, 1.0), j["shadow_fraction"].get<double>());
  if (j.contains("max_excess"))
    p.max_excess = (r.number(j["max_excess"], at + "/max_excess", 0.0, 1e6), j["max_excess"].get<double>());
  if (j.contains("chains")) p.chains = r.uint(j["chains"], at + "/chains", 3, kMaxChains);
  return p;
}

struct LeakFrame {
  std::uint32_t frame = 0, window_frames = 0;
  std::size_t pixels = 0;
  double energy_ratio = 0.0, sigma = 0.0, limit = 0.0, whole_image_ratio = 0.0;
  bool leaks = false;
  std::string evidence;
  nlohmann::json region;  // the shadowed region's bounding box (CheckResult::region)
};

class LightLeakCheck final : public Check, ReferenceComparisons {
 public:
  explicit LightLeakCheck(const CheckContext& c) : LightLeakCheck(c, leak_params(c)) {}

  CheckNeeds needs() const override {
    return {.reads = {FrameInput::chains},
            .frames = std::set<std::uint32_t>(params_.frames.begin(), params_.frames.end()),
            .chains = leak_.chains,
            .warmup_frames = params_.warmup_frames};
  }

  void observe(const FrameView& f, nlohmann::json& record) override {
    std::vector<Image> means;
    for (std::uint32_t k = 0; k < f.chain_count(); ++k) means.push_back(f.chain_mean(k));
    const Reference ref = reference(f.scene(), means[0].width, means[0].height, false);
    double ref_sum = 0.0;
    for (const glm::vec3& p : ref.mean.pixels) ref_sum += lum(p);
    const double threshold = leak_.shadow_fraction * ref_sum / double(ref.mean.size());
    std::vector<bool> region(ref.mean.size());
    std::size_t pixels = 0;
    for (std::size_t i = 0; i < region.size(); ++i) pixels += region[i] = lum(ref.mean.pixels[i]) < threshold;
    std::vector<Image> in_region;
    for (const Image& m : means) in_region.push_back(masked(m, region));
    const Comparison whole = compare_chains(means, ref.mean, ref.half_a, ref.half_b);
    const Comparison c =
        compare_chains(in_region, masked(ref.mean, region), masked(ref.half_a, region), masked(ref.half_b, region));
    LeakFrame l;
    l.frame = f.frame();
    l.window_frames = f.chain_window_frames();
    l.pixels = pixels;
    l.energy_ratio = c.energy_ratio;
    l.sigma = c.energy_ratio_sigma;
    l.limit = 1.0 + leak_.max_excess + Comparison::noise_margin(c.energy_dof) * c.energy_ratio_sigma;
    l.whole_image_ratio = whole.energy_ratio;
    l.region = mask_bounds(region, ref.mean.width);
    l.leaks = pixels > 0 && c.energy_ratio > l.limit;
    const Image mean = chain_average(means);
    record["light_leak"] = {{"shadowed_pixels", pixels}, {"energy_ratio", json_figure(c.energy_ratio)}};
    // Evidence: where the region is and what each side put there.
    Image region_image(ref.mean.width, ref.mean.height);
    for (std::size_t i = 0; i < region.size(); ++i) region_image.pixels[i] = glm::vec3(region[i] ? 1.0f : 0.0f);
    l.evidence = fmt::format("light_leak/frame_{:05}.exr", f.frame());
    const Image realtime_in_region = masked(mean, region), reference_in_region = masked(ref.mean, region);
    write_exr(out_dir_ / l.evidence, {{"gpu_temporal_mean", &mean},
                                      {"embree_full_gi", &ref.mean},
                                      {"shadowed_region", &region_image},
                                      {"gpu_in_region", &realtime_in_region},
                                      {"embree_in_region", &reference_in_region}});
    frames_.push_back(l);
  }

  CheckResult result() override {
    CheckResult r;
    r.name = "light_leak";
    r.limits = {{"shadow_fraction", leak_.shadow_fraction}, {"max_excess", leak_.max_excess},
                {"chains", leak_.chains}, {"spp", params_.spp}};
    nlohmann::json list = nlohmann::json::array();
    const LeakFrame* worst = nullptr;
    for (const LeakFrame& l : frames_) {
      list.push_back({{"frame", l.frame},
                      {"window_frames", l.window_frames},
                      {"shadowed_pixels", l.pixels},
                      {"shadowed_energy_ratio", json_figure(l.energy_ratio)},
                      {"shadowed_energy_ratio_sigma", json_figure(l.sigma)},
                      {"limit", json_figure(l.limit)},
                      {"whole_image_energy_ratio", json_figure(l.whole_image_ratio)}});
      r.evidence.push_back(l.evidence);
      if (l.leaks && !r.first_failing_frame) r.first_failing_frame = l.frame;
      if (!worst || l.energy_ratio > worst->energy_ratio) worst = &l;
    }
    r.figures = {{"frames", list}};
    if (!worst || worst->pixels == 0) {
      r.verdict = Verdict::inconclusive;
      r.message = "no judged frame had a shadowed region (reference luminance below shadow_fraction of its mean)";
      return r;
    }
    r.figures["max_shadowed_energy_ratio"] = json_figure(worst->energy_ratio);
    // The region the verdict is about: the first leaking frame's, else the worst's.
    const LeakFrame* shown = worst;
    for (const LeakFrame& l : frames_)
      if (r.first_failing_frame && l.frame == *r.first_failing_frame) shown = &l;
    r.region = shown->region;
    r.region_mask = {{"file", shown->evidence}, {"layer", "shadowed_region"}};
    r.verdict = r.first_failing_frame ? Verdict::fail : Verdict::pass;
    r.message = fmt::format("frame {}: in the shadowed region ({} pixels with reference luminance below {:.2f} of its "
                            "mean) the realtime image has {:.3f} of the path tracer's energy (1 sigma {:.3f} from {} "
                            "chains; limit {:.3f} = 1 + {:.2f} + t sigma; whole image {:.3f}){}",
                            worst->frame, worst->pixels, leak_.shadow_fraction, worst->energy_ratio, worst->sigma,
                            leak_.chains, worst->limit, leak_.max_excess, worst->whole_image_ratio,
                            r.verdict == Verdict::fail ? ": light leaks into shadow" : "");
    return r;
  }

 private:
  LightLeakCheck(const CheckContext& c, LeakParams p)
      : ReferenceComparisons(p.reference, c.seed, cache_root() / "reference", c.options.out_dir), leak_(std::move(p)) {}

  LeakParams leak_;
  std::vector<LeakFrame> frames_;
};

constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "Light where the path tracer has shadow (Bevy #22252, #22348, #24332): on each judged frame, the realtime temporal mean of K independent chains against the Embree full path tracer over the shadowed region only (reference luminance below shadow_fraction of its mean). Fails when the region's energy ratio exceeds 1 + max_excess + q sigma, q Student's t at one-sided 0.135 %. Realtime mode with \"gi\": true.",
  "properties": {
    "name": {
      "const": "light_leak"
    },
    "frames": {
      "type": "array",
      "minItems": 1,
      "items": {
        "$ref": "#/$defs/frame"
      },
      "description": "Frames judged (default: the last)."
    },
    "spp": {
      "type": "integer",
      "minimum": 2,
      "maximum": 16777216,
      "description": "Reference samples per pixel (default 256; the reference check's renders are shared through the cache)."
    },
    "warmup_frames": {
      "type": "integer",
      "minimum": 0,
      "description": "Frames after the start of each static window left out of the temporal mean (default 0)."
    },
    "shadow_fraction": {
      "type": "number",
      "minimum": 0,
      "maximum": 1,
      "description": "The shadowed region: pixels whose reference luminance is below this fraction of the reference's mean (default 0.2)."
    },
    "max_excess": {
      "type": "number",
      "minimum": 0,
      "description": "Largest allowed excess of realtime over reference energy in the shadowed region, beyond the noise margin (default 0.1): the fixed pipeline's own excess in the scene, taken from its mean over seeds."
    },
    "chains": {
      "type": "integer",
      "minimum": 3,
      "maximum": 16,
      "description": "Independent chains, each a pipeline of its own (default 8: Student's t with 7 degrees of freedom puts the margin at 1.6 sigma of one chain; with 4 it would be 4.6); the energy sigma comes from their spread."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the energy ratio of the mean of K independent chains against the Embree path tracer over the "
    "shadowed region (reference luminance below shadow_fraction of its mean)",
    "the spread of the chains' region energies / sqrt(K), K - 1 degrees of freedom (it holds the "
    "world cache's error a chain shares over the region)",
    CheckModel::Basis::derived,
    0.00135,
    "one-sided 0.135 % (1 + max_excess + Student's t quantile x sigma) when the pipeline's true "
    "excess is at most max_excess"};

const RegisteredCheck<LightLeakCheck> kRegistration{{"light_leak", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
