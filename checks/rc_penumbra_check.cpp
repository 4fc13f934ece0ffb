// The rc_penumbra check (the lesson's closing remark: "when probe
// spacing becomes larger than the shadow detail scale, interpolation blurs
// light-dark boundaries"). Over the scenario's `region`, where the reference
// shows shadow detail (the stripes behind a grating, a sharp edge), each
// line across the detail (`across`: the axis it varies along) less its own
// mean, so the slow falloff from the light drops out. The figure is the
// share of the reference's detail the output reproduces: the regression
// slope of output on reference, Σ o'r' / (Σ r'² − the reference's noise
// variance). 1 keeps it all, 0 blurs it away; artefacts of the output's
// own that do not follow the reference do not count as detail. Fails below
// `min_kept`; inconclusive where the reference's detail is within three
// times its noise.
#include <cmath>

#include <fmt/format.h>

#include "core/rc/rc_reference.h"
#include "checks/check_registry.h"
#include "checks/rc_frame_check_base.h"

namespace gi {
namespace {

class RcPenumbraCheck final : public RcFrameCheck {
 public:
  explicit RcPenumbraCheck(const CheckContext& c) : RcFrameCheck(c, "rc_penumbra") {
    const nlohmann::json& p = c.spec.params;
    region_ = required_region("region", "the shadow detail");
    if (p.contains("min_kept")) min_kept_ = reader_.number(p["min_kept"], c.spec.json_path + "/min_kept", 0.0, 1.0);
    if (p.contains("across")) across_ = reader_.one_of(p["across"], c.spec.json_path + "/across", {"x", "y"});
  }

 private:
  bool larger_is_worse() const override { return false; }
  Judgement judge(const FrameView&, const Image& out, const RcReference& ref) override {
    // Per line of the region along the detail (a column when it varies
    // along y), deviations from that line's mean: the slow falloff away
    // from the light drops out, the stripes stay.
    const bool along_y = across_ == "y";
    const std::uint32_t lines = along_y ? region_.x1 - region_.x0 : region_.y1 - region_.y0;
    const std::uint32_t length = along_y ? region_.y1 - region_.y0 : region_.x1 - region_.x0;
    double cross = 0, ref_var = 0, out_var = 0, noise_var = 0, n = 0;
    for (std::uint32_t l = 0; l < lines; ++l) {
      std::vector<double> o, r, v;
      for (std::uint32_t t = 0; t < length; ++t) {
        const std::uint32_t x = along_y ? region_.x0 + l : region_.x0 + t, y = along_y ? region_.y0 + t : region_.y0 + l;
        const std::size_t i = std::size_t(y) * out.width + x;
        if (!ref.free[i]) continue;
        o.push_back(rc_luminance(out.pixels[i]));
        r.push_back(rc_luminance(ref.mean.pixels[i]));
        const double d = rc_luminance(ref.half_a.pixels[i]) - rc_luminance(ref.half_b.pixels[i]);
        v.push_back(d * d / 4);
      }
      if (o.size() < 2) continue;
      double om = 0, rm = 0;
      for (std::size_t k = 0; k < o.size(); ++k) om += o[k], rm += r[k];
      om /= double(o.size()), rm /= double(o.size());
      for (std::size_t k = 0; k < o.size(); ++k) {
        cross += (o[k] - om) * (r[k] - rm);
        ref_var += (r[k] - rm) * (r[k] - rm);
        out_var += (o[k] - om) * (o[k] - om);
        noise_var += v[k];
        n += 1;
      }
    }
    Judgement j;
    // The reference's detail less its own noise; the share of it the output
    // reproduces is the regression slope of output on reference.
    const double detail = std::max(ref_var - noise_var, 0.0);
    const double kept = detail > 0 ? cross / detail : 0.0;
    j.figure = kept;
    j.figures = {{"detail_kept", kept}, {"output_std", n > 0 ? std::sqrt(out_var / n) : 0.0},
                 {"reference_std", n > 0 ? std::sqrt(detail / n) : 0.0},
                 {"reference_noise_std", n > 0 ? std::sqrt(noise_var / n) : 0.0}, {"region_pixels", n},
                 {"region", region_.to_json()}, {"across", across_}};
    // A reference whose detail is not well above its own noise cannot judge.
    j.verdict = detail <= 3 * noise_var ? Verdict::inconclusive : kept < min_kept_ ? Verdict::fail : Verdict::pass;
    return j;
  }
  std::string describe(const Judgement& j, std::uint32_t frame) const override {
    return fmt::format("frame {}: the output reproduces {:.3f} of the reference's shadow detail (reference std {:.4f} "
                       "along {}; at least {:.2f})",
                       frame, j.figures["detail_kept"].get<double>(), j.figures["reference_std"].get<double>(), across_,
                       min_kept_);
  }
  nlohmann::json limits() const override { return {{"min_kept", min_kept_}, {"region", region_.to_json()}, {"across", across_}}; }

  RcRegion region_;
  double min_kept_ = 0.6;
  std::string across_ = "y";
};

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the share of the reference's shadow detail the output reproduces (regression slope of output on "
    "reference across the detail)",
    "the reference's noise variance, subtracted from its detail; inconclusive where the detail is "
    "within 3 times it",
    CheckModel::Basis::derived,
    0.00135,
    "one-sided 0.135 % where the reference's noise is what moves the figure (the cascades are "
    "deterministic); the output's figure is the same at every seed"};

const RegisteredCheck<RcPenumbraCheck> kRegistration{{"rc_penumbra",
    rc_check_schema("rc_penumbra", R"j("region": {"type": "array", "minItems": 4, "maxItems": 4, "items": {"type": "integer", "minimum": 0}, "description": "[x0, y0, x1, y1]: where the reference shows shadow detail, pixels (required)"},
    "min_kept": {"type": "number", "minimum": 0, "maximum": 1, "description": "smallest share of the reference's shadow detail the output reproduces (default 0.6)"},
    "across": {"enum": ["x", "y"], "description": "the axis the detail varies along (default y: horizontal stripes)"})j"),
    kModel, {}}};

}  // namespace
}  // namespace gi
