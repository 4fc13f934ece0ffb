// The rc_reference check: does the radiance-cascades output
// converge to the 2D path tracer's? Over the pixels outside every shape,
// the relative error Σ|Y_rc − Y_ref| / ΣY_ref (luminance), held to
// `max_error` plus three times the reference's own noise there (its two
// half estimates), so a noisy reference cannot fail a good pipeline; when
// that noise alone is a third of the limit the verdict is inconclusive.
// The signed bias (ΣY_rc / ΣY_ref − 1) is reported beside it; rc_energy judges it.
#include <fmt/format.h>

#include "core/rc/rc_reference.h"
#include "checks/check_registry.h"
#include "checks/rc_frame_check_base.h"

namespace gi {
namespace {

class RcReferenceCheck final : public RcFrameCheck {
 public:
  explicit RcReferenceCheck(const CheckContext& c) : RcFrameCheck(c, "rc_reference") {
    const nlohmann::json& p = c.spec.params;
    if (p.contains("max_error")) max_error_ = reader_.number(p["max_error"], c.spec.json_path + "/max_error", 0.0, 100.0);
  }

 private:
  Judgement judge(const FrameView&, const Image& out, const RcReference& ref) override {
    const RcComparison c = rc_compare(out, ref);
    Judgement j;
    const double e = c.relative_l1(), n = c.reference > 0 ? c.noise_abs / c.reference : 0.0;
    j.figure = e;
    j.figures = {{"relative_error", e}, {"bias", c.reference > 0 ? c.energy_ratio() - 1.0 : 0.0},
                 {"reference_noise", n}, {"tolerance", max_error_ + 3 * n}, {"reference_rays", ref.rays}};
    j.verdict = c.reference <= 0 || 3 * n > max_error_ ? Verdict::inconclusive
                : e > max_error_ + 3 * n              ? Verdict::fail
                                                      : Verdict::pass;
    return j;
  }
  std::string describe(const Judgement& j, std::uint32_t frame) const override {
    return fmt::format("frame {}: relative error {:.3f} against the 2D path tracer (limit {:.3f} + 3 x noise {:.4f}), "
                       "bias {:+.3f}",
                       frame, j.figures["relative_error"].get<double>(), max_error_,
                       j.figures["reference_noise"].get<double>(), j.figures["bias"].get<double>());
  }
  nlohmann::json limits() const override { return {{"max_error", max_error_}}; }

  double max_error_ = 0.25;
};

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the relative L1 error of the radiance-cascades output against the 2D path tracer outside the "
    "shapes",
    "the reference's own noise there, from its two half estimates; the cascades themselves draw no "
    "random number",
    CheckModel::Basis::derived,
    0.00135,
    "one-sided 0.135 % (max_error + 3 sigma of a normal); inconclusive where the noise alone is a "
    "third of the limit"};

const RegisteredCheck<RcReferenceCheck> kRegistration{{"rc_reference",
    rc_check_schema("rc_reference", R"j("max_error": {"type": "number", "minimum": 0, "description": "largest sum of |output - reference| over the reference's sum, outside the shapes (default 0.25)"})j"),
    kModel, {}}};

}  // namespace
}  // namespace gi
