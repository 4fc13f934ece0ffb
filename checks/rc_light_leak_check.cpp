// The rc_light_leak check: light through occluders thinner than
// a probe spacing. A probe's rays start at the probe centre, and merging
// interpolates between coarser probes up to twice the spacing apart: both
// reach across a wall thinner than that, so the shadowed side receives
// the lit side's radiance. Over the scenario's `region` (the shadowed
// side), the excess of the output's mean luminance over the reference's,
// as a fraction of the reference's mean over the whole canvas, held to
// `max_leak` plus three standard deviations of the reference there.
#include <cmath>

#include <fmt/format.h>

#include "core/rc/rc_reference.h"
#include "checks/check_registry.h"
#include "checks/rc_frame_check_base.h"

namespace gi {
namespace {

class RcLightLeakCheck final : public RcFrameCheck {
 public:
  explicit RcLightLeakCheck(const CheckContext& c) : RcFrameCheck(c, "rc_light_leak") {
    const nlohmann::json& p = c.spec.params;
    region_ = required_region("region", "the shadowed side");
    if (p.contains("max_leak")) max_leak_ = reader_.number(p["max_leak"], c.spec.json_path + "/max_leak", 0.0, 100.0);
  }

 private:
  Judgement judge(const FrameView&, const Image& out, const RcReference& ref) override {
    const RcComparison all = rc_compare(out, ref), in = region_.compare(out, ref);
    Judgement j;
    const double mean_all = all.pixels ? all.reference / double(all.pixels) : 0.0;
    const double n = double(std::max<std::size_t>(in.pixels, 1));
    const double leak = mean_all > 0 ? (in.output - in.reference) / n / mean_all : 0.0;
    const double sigma = mean_all > 0 ? std::sqrt(in.noise_var) / n / mean_all : 0.0;
    j.figure = leak;
    j.figures = {{"leak", leak}, {"sigma", sigma}, {"region_output_mean", in.output / n},
                 {"region_reference_mean", in.reference / n}, {"canvas_reference_mean", mean_all},
                 {"region_pixels", in.pixels}, {"region", region_.to_json()}};
    j.verdict = in.pixels == 0 || mean_all <= 0 ? Verdict::inconclusive
                : leak > max_leak_ + 3 * sigma ? Verdict::fail
                                               : Verdict::pass;
    return j;
  }
  std::string describe(const Judgement& j, std::uint32_t frame) const override {
    return fmt::format("frame {}: {:+.3f} of the canvas's mean radiance leaks into the shadowed region "
                       "(output {:.4f}, reference {:.4f}; limit {:.3f} + 3 x {:.4f})",
                       frame, j.figures["leak"].get<double>(), j.figures["region_output_mean"].get<double>(),
                       j.figures["region_reference_mean"].get<double>(), max_leak_, j.figures["sigma"].get<double>());
  }
  nlohmann::json limits() const override { return {{"max_leak", max_leak_}, {"region", region_.to_json()}}; }

  RcRegion region_;
  double max_leak_ = 0.05;
};

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the excess of the output's mean over the reference's in the shadowed region, as a fraction of "
    "the canvas's mean",
    "the reference's standard deviation in the region, from its two half estimates",
    CheckModel::Basis::derived,
    0.00135,
    "one-sided 0.135 % (max_leak + 3 sigma of a normal)"};

const RegisteredCheck<RcLightLeakCheck> kRegistration{{"rc_light_leak",
    rc_check_schema("rc_light_leak", R"j("region": {"type": "array", "minItems": 4, "maxItems": 4, "items": {"type": "integer", "minimum": 0}, "description": "[x0, y0, x1, y1]: the shadowed side, pixels (required)"},
    "max_leak": {"type": "number", "minimum": 0, "description": "largest excess of the region's mean over the reference's, as a fraction of the canvas's mean (default 0.05)"})j"),
    kModel, {}}};

}  // namespace
}  // namespace gi
