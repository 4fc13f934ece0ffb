// The rc_energy check: the radiance-cascades output's energy
// against the 2D path tracer's, ΣY_rc / ΣY_ref over the pixels outside every
// shape, within [1 − max_loss, 1 + max_gain] widened by three standard
// deviations of the reference's sum. A normalisation that is off by a
// factor (the lesson's mipmap divisor at resolution_factor ≠ 1) or rays
// that never reach the light show here first.
#include <cmath>

#include <fmt/format.h>

#include "core/rc/rc_reference.h"
#include "checks/check_registry.h"
#include "checks/rc_frame_check_base.h"

namespace gi {
namespace {

class RcEnergyCheck final : public RcFrameCheck {
 public:
  explicit RcEnergyCheck(const CheckContext& c) : RcFrameCheck(c, "rc_energy") {
    const nlohmann::json& p = c.spec.params;
    const std::string& at = c.spec.json_path;
    if (p.contains("max_gain")) max_gain_ = reader_.number(p["max_gain"], at + "/max_gain", 0.0, 100.0);
    if (p.contains("max_loss")) max_loss_ = reader_.number(p["max_loss"], at + "/max_loss", 0.0, 1.0);
  }

 private:
  Judgement judge(const FrameView&, const Image& out, const RcReference& ref) override {
    const RcComparison s = rc_compare(out, ref);
    Judgement j;
    const double ratio = s.energy_ratio();
    const double sigma = s.reference > 0 ? ratio * std::sqrt(s.noise_var) / s.reference : 0.0;
    j.figure = std::abs(ratio - 1.0);
    j.figures = {{"energy_ratio", ratio}, {"sigma", sigma}, {"pixels", s.pixels}};
    j.verdict = s.reference <= 0                                                                  ? Verdict::inconclusive
                : ratio > 1 + max_gain_ + 3 * sigma || ratio < 1 - max_loss_ - 3 * sigma ? Verdict::fail
                                                                                         : Verdict::pass;
    return j;
  }
  std::string describe(const Judgement& j, std::uint32_t frame) const override {
    return fmt::format("frame {}: energy {:.3f} of the 2D path tracer's outside the shapes (allowed {:.3f} to {:.3f}, "
                       "sigma {:.4f})",
                       frame, j.figures["energy_ratio"].get<double>(), 1 - max_loss_, 1 + max_gain_,
                       j.figures["sigma"].get<double>());
  }
  nlohmann::json limits() const override { return {{"max_gain", max_gain_}, {"max_loss", max_loss_}}; }

  double max_gain_ = 0.1, max_loss_ = 0.1;
};

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the ratio of the output's energy to the 2D path tracer's outside the shapes",
    "the reference sum's standard deviation, from its two half estimates; the cascades draw no random"
    " number",
    CheckModel::Basis::derived,
    0.0027,
    "two-sided 0.27 % ([1 - max_loss, 1 + max_gain] widened by 3 sigma of a normal on each side)"};

const RegisteredCheck<RcEnergyCheck> kRegistration{{"rc_energy",
    rc_check_schema("rc_energy", R"j("max_gain": {"type": "number", "minimum": 0, "description": "largest excess of the energy ratio over 1 (default 0.1)"},
    "max_loss": {"type": "number", "minimum": 0, "maximum": 1, "description": "largest shortfall of the energy ratio under 1 (default 0.1)"})j"),
    kModel, {}}};

}  // namespace
}  // namespace gi
