// The motion check: the realtime image while the camera or an object moves.
// `reference` judges temporal means over static windows; a reprojection error
// (history read from the wrong pixel, history kept across a disocclusion)
// shows only in frames that move, so this check judges those.
//
// On each judged frame (moving frames and the `trail_frames` after each, from
// `first_frame` on, at least `stride` apart)
// the mean x = (A + B)/2 of the two chains' frames (two pipelines that share
// no state) is compared with Embree's image r of that frame's camera and
// scene (direct light; with "gi": true the full path tracer), per pixel and
// channel:
//   e = [(x − r)² − (A − B)²/4 − (r_a − r_b)²/4] / (r² + 0.01)
// (A − B)²/4 estimates x's own noise, (r_a − r_b)²/4 the reference's, so e
// is an unbiased estimate of the squared bias, relative as relMSE is:
// E[mean e] = bias relMSE. The per-frame noise is removed, not averaged away.
//
// Statistical model: the judged frames' e, averaged over 8×8-pixel blocks
// (so noise shared by nearby pixels, a cache cell or a reused reservoir, is
// counted as such), are the units; their mean is the bias relMSE and their
// standard error SE its noise. The check fails when
//   bias relMSE > tolerance + z · SE,   z = 3.09 (one-sided 0.1 %),
// so a pipeline whose true bias is at most `tolerance` raises a false alarm
// at about 0.1 % of seeds (normal approximation over ≥ 50 blocks). The
// tolerance is the fixed pipeline's own bias under motion (a temporal
// pipeline lags a moving view a little), stated per scenario with the
// measured spread; tests count the alarms over seeds.
//
// The disocclusion figure: the same estimate over the pixels whose surface
// the previous frame did not see (off screen, or its depth at the
// reprojected pixel a point more than 10 % of the distance away), where
// history must not be kept (both from the scene's cameras, not from the
// pipeline's motion vectors); with `disocclusion_tolerance` it is judged the same way.
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "core/cache_root.h"
#include "core/json_reader.h"
#include "core/metrics.h"
#include "core/scene_flatten.h"
#include "gpu/shaders/gbuffer.h"
#include "core/shared/host_device.h"
#include "checks/check_registry.h"
#include "checks/realtime_reference_check.h"
#include "core/scene_events.h"
#include "core/run_options.h"
#include "reports/json_figures.h"

namespace gi {
namespace {

constexpr double kZ = 3.09;             // one-sided 0.1 % of the standard normal
constexpr std::uint32_t kBlock = 8;     // pixels per side of a unit of the standard error
constexpr double kDepthChange = 0.10;   // relative depth change that makes a pixel disoccluded

struct MotionParams {
  ReferenceCheckParams reference;  // judged frames, spp
  std::uint32_t first_frame = 16, stride = 4, trail_frames = 2;
  double tolerance = 0.0;
  std::optional<double> disocclusion_tolerance;
  bool full_gi = false;
};

// The frames where the camera or an instance moved since the last frame.
std::vector<std::uint32_t> moving_frames(const CheckContext& c) {
  std::vector<std::uint32_t> moving;
  Scene scene = c.initial;
  for (std::uint32_t f = 0; f < c.frames; ++f) {
    const ChangeSet changes = apply_events(scene, c.initial, c.scenario, f);
    if (f > 0 && (changes.camera || changes.transforms)) moving.push_back(f);
  }
  return moving;
}

MotionParams motion_params(const CheckContext& c) {
  if (!c.realtime) c.refuse("", "judges the realtime pipeline's frames (\"mode\": \"realtime\")");
  MotionParams p;
  p.full_gi = c.gi;
  p.reference.spp = 128;
  const JsonReader r(c.scenario.file.string());
  const nlohmann::json& j = c.spec.params;
  const std::string& at = c.spec.json_path;
  if (j.contains("first_frame")) p.first_frame = r.uint(j["first_frame"], at + "/first_frame", 1, kMaxFrames - 1);
  if (j.contains("stride")) p.stride = r.uint(j["stride"], at + "/stride", 1, 1024);
  if (j.contains("spp")) p.reference.spp = r.uint(j["spp"], at + "/spp", 2, 1u << 24);
  if (j.contains("tolerance"))
    p.tolerance = (r.number(j["tolerance"], at + "/tolerance", 0.0, 1e6), j["tolerance"].get<double>());
  if (j.contains("disocclusion_tolerance"))
    p.disocclusion_tolerance = (r.number(j["disocclusion_tolerance"], at + "/disocclusion_tolerance", 0.0, 1e6),
                                j["disocclusion_tolerance"].get<double>());
  if (j.contains("trail_frames")) p.trail_frames = r.uint(j["trail_frames"], at + "/trail_frames", 0, 1024);
  // Moving frames and the trail_frames after each, where a history bug lingers.
  std::set<std::uint32_t> candidates;
  for (std::uint32_t f : moving_frames(c))
    for (std::uint32_t t = f; t <= f + p.trail_frames && t < c.frames; ++t) candidates.insert(t);
  if (j.contains("frames")) {  // the frames to judge, as given (the scenario knows where it moves)
    const nlohmann::json& f = r.array(j["frames"], at + "/frames", 1);
    for (std::size_t i = 0; i < f.size(); ++i)
      p.reference.frames.push_back(r.uint(f[i], JsonReader::at(at + "/frames", i), 1, c.frames - 1));
    return p;
  }
  std::uint32_t next = p.first_frame;
  for (std::uint32_t f : candidates)
    if (f >= next) {
      p.reference.frames.push_back(f);
      next = f + p.stride;
    }
  if (p.reference.frames.empty())
    c.refuse("first_frame", fmt::format("no frame from {} on moves the camera or an object (of {} frames)",
                                        p.first_frame, c.frames));
  return p;
}

// The bias estimate over a set of pixels: block means of e, their mean and
// standard error.
struct BiasEstimate {
  double bias_relmse = 0.0, standard_error = 0.0, relmse = 0.0, noise = 0.0;
  std::size_t pixels = 0, blocks = 0;
  // One-sided test against a tolerance.
  bool exceeds(double tolerance) const { return bias_relmse > tolerance + kZ * standard_error; }
  nlohmann::json json() const {
    return {{"bias_relmse", json_figure(bias_relmse)}, {"standard_error", json_figure(standard_error)},
            {"relmse", json_figure(relmse)}, {"noise", json_figure(noise)}, {"pixels", pixels}, {"blocks", blocks}};
  }
};

// Accumulates e per block over the judged frames (blocks of different frames
// are different units: the camera moved).
class BiasAccumulator {
 public:
  void add_frame(const Image& a, const Image& b, const Image& r, const Image& ra, const Image& rb,
                 const std::vector<bool>* only) {
    for (std::uint32_t by = 0; by < r.height; by += kBlock)
      for (std::uint32_t bx = 0; bx < r.width; bx += kBlock) {
        double e_sum = 0.0, relmse_sum = 0.0, noise_sum = 0.0;
        std::size_t n = 0;
        for (std::uint32_t y = by; y < std::min(by + kBlock, r.height); ++y)
          for (std::uint32_t x = bx; x < std::min(bx + kBlock, r.width); ++x) {
            const std::size_t i = std::size_t(y) * r.width + x;
            if (only && !(*only)[i]) continue;
            bool finite = true;
            for (const Image* img : {&a, &b, &r, &ra, &rb})
              for (int ch = 0; ch < 3; ++ch) finite = finite && std::isfinite(img->pixels[i][ch]);
            if (!finite) continue;
            for (int ch = 0; ch < 3; ++ch) {
              const double av = a.pixels[i][ch], bv = b.pixels[i][ch], rv = r.pixels[i][ch];
              const double den = rv * rv + kRelmseEpsilon;
              const double xv = 0.5 * (av + bv), d_ref = double(ra.pixels[i][ch]) - rb.pixels[i][ch];
              const double err = (xv - rv) * (xv - rv) / den;
              const double noise = ((av - bv) * (av - bv) + d_ref * d_ref) / 4.0 / den;
              e_sum += err - noise;
              relmse_sum += err;
              noise_sum += noise;
            }
            ++n;
          }
        if (n == 0) continue;
        block_means_.push_back(e_sum / double(3 * n));
        block_weights_.push_back(double(n));
        relmse_sum_ += relmse_sum;
        noise_sum_ += noise_sum;
        pixels_ += n;
      }
  }
  BiasEstimate estimate() const {
    BiasEstimate e;
    e.pixels = pixels_;
    e.blocks = block_means_.size();
    if (pixels_ == 0) return e;
    // Pixel-weighted mean of the block means (= the mean over pixels), and the
    // standard error of a weighted mean of independent units.
    double w_sum = 0.0, mean = 0.0;
    for (std::size_t k = 0; k < block_means_.size(); ++k) w_sum += block_weights_[k], mean += block_weights_[k] * block_means_[k];
    mean /= w_sum;
    double var = 0.0, w2 = 0.0;
    for (std::size_t k = 0; k < block_means_.size(); ++k) {
      const double d = block_means_[k] - mean;
      var += block_weights_[k] * block_weights_[k] * d * d;
      w2 += block_weights_[k] * block_weights_[k];
    }
    const double units = double(block_means_.size());
    e.bias_relmse = mean;
    e.standard_error = units > 1 ? std::sqrt(var / (w_sum * w_sum) * units / (units - 1.0)) : INFINITY;
    e.relmse = relmse_sum_ / double(3 * pixels_);
    e.noise = noise_sum_ / double(3 * pixels_);
    return e;
  }

 private:
  std::vector<double> block_means_, block_weights_;
  double relmse_sum_ = 0.0, noise_sum_ = 0.0;
  std::size_t pixels_ = 0;
};

class MotionCheck final : public Check, ReferenceComparisons {
 public:
  explicit MotionCheck(const CheckContext& c) : MotionCheck(c, motion_params(c)) {}

  CheckNeeds needs() const override {
    std::set<std::uint32_t> frames;
    for (std::uint32_t f : params_.frames) frames.insert({f - 1, f});  // f − 1: its depth, for disocclusions
    return {.reads = {FrameInput::chains, FrameInput::gbuffer_layers}, .frames = frames, .chains = 2};
  }

  void observe(const FrameView& f, nlohmann::json& record) override {
    const Image position = f.gbuffer_layer("position"), depth = f.gbuffer_layer("depth");
    const bool judged = wants(f.frame());
    const std::vector<bool> disoccluded =
        judged && previous_frame_ + 1 == f.frame() ? disocclusions(position, depth) : std::vector<bool>(depth.size(), false);
    previous_position_ = position;
    previous_camera_ = make_gpu_camera(f.scene().camera, position.width, position.height);
    previous_frame_ = f.frame();
    if (!judged) return;
    const Image a = f.chain_frame(0), b = f.chain_frame(1);
    const Reference ref = reference(f.scene(), a.width, a.height, !motion_.full_gi);
    BiasAccumulator frame_all, frame_disoccluded;
    for (BiasAccumulator* acc : {&all_, &frame_all}) acc->add_frame(a, b, ref.mean, ref.half_a, ref.half_b, nullptr);
    for (BiasAccumulator* acc : {&disoccluded_, &frame_disoccluded})
      acc->add_frame(a, b, ref.mean, ref.half_a, ref.half_b, &disoccluded);
    nlohmann::json row = {{"frame", f.frame()},
                          {"all", frame_all.estimate().json()},
                          {"disoccluded", frame_disoccluded.estimate().json()}};
    record["motion"] = row;
    rows_.push_back(row);
  }

  CheckResult result() override {
    CheckResult r;
    r.name = "motion";
    r.limits = {{"tolerance", motion_.tolerance},
                {"z", kZ},
                {"spp", params_.spp},
                {"block_pixels", kBlock}};
    if (motion_.disocclusion_tolerance) r.limits["disocclusion_tolerance"] = *motion_.disocclusion_tolerance;
    const BiasEstimate all = all_.estimate(), dis = disoccluded_.estimate();
    r.figures = {{"frames", rows_}, {"all", all.json()}, {"disoccluded", dis.json()},
                 {"bias_over_standard_error", json_figure(all.standard_error > 0 ? all.bias_relmse / all.standard_error : 0.0)}};
    if (rows_.empty()) {
      r.verdict = Verdict::inconclusive;
      r.message = "no moving frame was judged";
      return r;
    }
    const bool fails = all.exceeds(motion_.tolerance);
    const bool dis_fails = motion_.disocclusion_tolerance && dis.pixels > 0 && dis.exceeds(*motion_.disocclusion_tolerance);
    r.verdict = fails || dis_fails ? Verdict::fail : Verdict::pass;
    if (r.verdict == Verdict::fail) r.first_failing_frame = rows_.front()["frame"].get<std::uint32_t>();
    r.message = fmt::format(
        "{} moving frames: bias relMSE {:.3g} (SE {:.2g}; relMSE {:.3g}, noise {:.3g}) against tolerance {:.3g} + "
        "{:.2f} SE{}; disoccluded pixels {}: bias relMSE {:.3g} (SE {:.2g}){}",
        rows_.size(), all.bias_relmse, all.standard_error, all.relmse, all.noise, motion_.tolerance, kZ,
        fails ? ": the image under motion is biased beyond the pipeline's own lag" : "", dis.pixels, dis.bias_relmse,
        dis.standard_error, dis_fails ? ": history survives disocclusions" : "");
    return r;
  }

 private:
  MotionCheck(const CheckContext& c, MotionParams p)
      : ReferenceComparisons(p.reference, c.seed, cache_root() / "reference", c.options.out_dir), motion_(std::move(p)) {}

  // Pixels whose surface the previous frame did not see, from the scene's
  // cameras (not the pipeline's motion vectors, which a bug may get wrong):
  // the surface point projected into the previous camera lands off screen,
  // or the previous frame saw a point there more than kDepthChange of the
  // distance away.
  std::vector<bool> disocclusions(const Image& position, const Image& depth) const {
    std::vector<bool> out(depth.size(), false);
    if (previous_position_.size() != depth.size()) return out;
    const glm::uvec2 size(depth.width, depth.height);
    for (std::size_t i = 0; i < depth.size(); ++i) {
      if (!(depth.pixels[i].x > 0.0f)) continue;  // sky: no surface, no history
      const glm::vec3 p = position.pixels[i];
      glm::vec2 q;
      const bool in_front = shader::camera_project(previous_camera_, p, size, q);
      const int qx = int(std::floor(q.x)), qy = int(std::floor(q.y));
      if (!in_front || qx < 0 || qy < 0 || qx >= int(size.x) || qy >= int(size.y)) {
        out[i] = true;
        continue;
      }
      const glm::vec3 seen = previous_position_.pixels[std::size_t(qy) * size.x + qx];
      const float distance = glm::length(p - glm::vec3(previous_camera_.position));
      out[i] = !(glm::length(seen - p) <= kDepthChange * distance);
    }
    return out;
  }

  MotionParams motion_;
  Image previous_position_;  // the frame before a judged one: its G-buffer positions and camera
  GpuCamera previous_camera_{};
  std::uint32_t previous_frame_ = ~0u;
  BiasAccumulator all_, disoccluded_;
  nlohmann::json rows_ = nlohmann::json::array();
};

constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "The realtime image while the camera or an object moves, against Embree's image of each judged frame's camera and scene (direct light; with \"gi\": true the full path tracer). Per pixel and channel e = [(x - r)^2 - (A - B)^2/4 - (r_a - r_b)^2/4] / (r^2 + 0.01), x the mean of two chains A and B that share no state, r the reference with halves r_a, r_b; E[e] is the squared bias (relMSE's scale), the per-frame noise removed. Units: 8x8-pixel blocks of each judged frame; the check fails when their mean (the bias relMSE) exceeds tolerance + 3.09 standard errors. The same estimate over the pixels the previous frame did not see (disocclusions) is reported, and judged with disocclusion_tolerance.",
  "properties": {
    "name": {
      "const": "motion"
    },
    "frames": {
      "type": "array",
      "minItems": 1,
      "items": {
        "$ref": "#/$defs/frame"
      },
      "description": "The frames to judge, instead of the moving frames the scenario's events give (each at least 1: the frame before it is read too)."
    },
    "first_frame": {
      "type": "integer",
      "minimum": 1,
      "description": "The first frame judged: moving frames from this one on (default 16: after the caches' first warm-up)."
    },
    "trail_frames": {
      "type": "integer",
      "minimum": 0,
      "maximum": 1024,
      "description": "Frames after each move that are judged too: where history a move invalidated lingers (default 2)."
    },
    "stride": {
      "type": "integer",
      "minimum": 1,
      "maximum": 1024,
      "description": "At least this many frames between judged frames (default 4)."
    },
    "tolerance": {
      "type": "number",
      "minimum": 0,
      "maximum": 1000000.0,
      "description": "The bias relMSE the fixed pipeline is allowed under motion (its own temporal lag; default 0)."
    },
    "disocclusion_tolerance": {
      "type": "number",
      "minimum": 0,
      "maximum": 1000000.0,
      "description": "When given, the disoccluded pixels' bias relMSE is judged against it the same way."
    },
    "spp": {
      "type": "integer",
      "minimum": 2,
      "maximum": 16777216,
      "description": "Reference samples per pixel (default 128)."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the bias relMSE of two independent chains' mean against Embree at each judged frame's camera and"
    " scene, per-frame noise removed ([(x - r)^2 - (A - B)^2/4 - (r_a - r_b)^2/4] / (r^2 + 0.01) per "
    "pixel), and the same over disoccluded pixels",
    "the standard error over 8x8-pixel blocks of the judged frames (noise shared by nearby pixels "
    "counts once)",
    CheckModel::Basis::derived,
    0.001,
    "one-sided 0.1 % per test (tolerance + 3.09 SE, normal over at least 50 blocks) when the true "
    "bias is at most the tolerance"};

const RegisteredCheck<MotionCheck> kRegistration{{"motion", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
