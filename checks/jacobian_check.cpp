#include "checks/jacobian_check.h"
#include "core/profile.h"
#include "checks/check_registry.h"
#include "gpu/realtime_settings.h"

#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "reports/json_figures.h"

namespace gi {

JacobianCheckParams jacobian_check_params(const CheckSpec& spec, const Scenario& scenario, double profile_reject) {
  JacobianCheckParams p;
  p.max_jacobian = profile_reject;
  if (spec.params.contains("max_jacobian")) {
    const nlohmann::json& v = spec.params["max_jacobian"];
    if (!v.is_number() || !(v.get<double>() > 0.0) || !std::isfinite(v.get<double>()))
      throw InputError(scenario.file.string(), spec.json_path + "/max_jacobian", "expected a number above 0");
    p.max_jacobian = v.get<double>();
  }
  return p;
}

nlohmann::json JacobianCheck::record_frame(std::uint32_t frame, const gpu::GiFrameStats& s) {
  ++frames_;
  merges_ += s.merges;
  rejections_ += s.rejections;
  nonfinite_jacobians_ += s.nonfinite_jacobians;
  nonfinite_reservoirs_ += s.nonfinite_reservoirs;
  nonfinite_output_ += s.nonfinite_output;
  const double j = s.max_accepted_j;
  if (!(j <= max_accepted_j_) && std::isfinite(j)) {
    max_accepted_j_ = j;
    max_accepted_j_frame_ = frame;
  }
  for (std::size_t b = 0; b < histogram_.size() && b < s.log2_j_histogram.size(); ++b)
    histogram_[b] += s.log2_j_histogram[b];
  if (!first_bad_frame_) {
    if (s.nonfinite_reservoirs > 0 || s.nonfinite_output > 0)
      first_bad_reason_ = fmt::format("{} non-finite GI reservoirs and {} non-finite output pixels",
                                      s.nonfinite_reservoirs, s.nonfinite_output);
    // The shaders compare J with the float threshold: J equal to float(1.2)
    // = 1.20000005 is accepted there and must be here.
    else if (!(j <= double(float(params_.max_jacobian))))
      first_bad_reason_ = fmt::format("accepted J = {:.6g} above {:.6g} ({} merges, {} rejected)", j,
                                      params_.max_jacobian, s.merges, s.rejections);
    if (!first_bad_reason_.empty()) first_bad_frame_ = frame;
  }
  return {{"merges", s.merges},
          {"rejections", s.rejections},
          {"max_accepted_j", json_figure(j)},
          {"nonfinite_jacobians", s.nonfinite_jacobians},
          {"nonfinite_reservoirs", s.nonfinite_reservoirs},
          {"nonfinite_output", s.nonfinite_output}};
}

CheckResult JacobianCheck::result() const {
  CheckResult r;
  r.name = "jacobian";
  r.limits = {{"max_jacobian", params_.max_jacobian}, {"nonfinite", 0}};
  nlohmann::json histogram = nlohmann::json::object();
  for (std::size_t b = 0; b < histogram_.size(); ++b)
    if (histogram_[b] > 0) histogram[fmt::format("2^{}", int(b) - 16)] = histogram_[b];
  r.figures = {{"frames", frames_},
               {"merges", merges_},
               {"rejections", rejections_},
               {"rejection_rate", json_figure(merges_ ? double(rejections_) / double(merges_) : 0.0)},
               {"max_accepted_j", json_figure(max_accepted_j_)},
               {"max_accepted_j_frame", max_accepted_j_frame_},
               {"nonfinite_jacobians_sanitised", nonfinite_jacobians_},
               {"nonfinite_reservoirs", nonfinite_reservoirs_},
               {"nonfinite_output", nonfinite_output_},
               {"log2_j_histogram", histogram}};
  if (frames_ == 0) {
    r.verdict = Verdict::inconclusive;
    r.message = "no frame was recorded";
    return r;
  }
  r.first_failing_frame = first_bad_frame_;
  r.verdict = first_bad_frame_ ? Verdict::fail : Verdict::pass;
  r.message = first_bad_frame_
                  ? fmt::format("frame {}: {}", *first_bad_frame_, first_bad_reason_)
                  : fmt::format("{} frames: {} merges, {} rejected, max accepted J {:.4g} ≤ {:.4g}, no non-finite value",
                                frames_, merges_, rejections_, max_accepted_j_, params_.max_jacobian);
  return r;
}


namespace {

// Reads GI's statistics each frame; its figures replace the frame record's
// plain "gi" entry.
class JacobianPlugin final : public Check {
 public:
  explicit JacobianPlugin(const CheckContext& c)
      : check_(jacobian_check_params(c.spec, c.scenario, c.resolved_settings().jacobian_reject)) {
    if (!c.gi) c.refuse("", "reads ReSTIR GI: a realtime scenario with \"gi\": true");
  }
  CheckNeeds needs() const override { return {.reads = {FrameInput::gi_stats}}; }
  void observe(const FrameView& f, nlohmann::json& record) override {
    record["gi"] = check_.record_frame(f.frame(), *f.gi_stats());
  }
  CheckResult result() override { return check_.result(); }

 private:
  JacobianCheck check_;
};

// This check's parameters as scenarios/schema.json states them ($defs/check_jacobian,
// which `giharness schema` writes from here); the parser accepts exactly
// these keys.
constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "ReSTIR GI jacobians (docs/design.md §6), from per-frame integer-atomic statistics: merges, rejections, max accepted J, a log2-J histogram, non-finite reservoirs and output. Fails on the first frame with a non-finite value or an accepted J above the limit. Needs \"gi\": true.",
  "properties": {
    "name": {
      "const": "jacobian"
    },
    "max_jacobian": {
      "type": "number",
      "exclusiveMinimum": 0,
      "description": "Largest allowed accepted J (default: the profile's restir_gi.jacobian_reject)."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the largest jacobian ReSTIR GI accepted, and non-finite reservoirs or outputs, from "
    "integer-atomic statistics of every merge",
    "none: the pipeline rejects a jacobian above the limit, so an accepted one above it is a bug at "
    "any seed",
    CheckModel::Basis::exact,
    0.0,
    "0: an invariant of the rejection rule (largest accepted J 1.199 to 1.2 against the limit 1.2 in "
    "the six GI scenes of the suite at 10 seeds)"};

const RegisteredCheck<JacobianPlugin> kRegistration{{"jacobian", kSchema, kModel, {}}};

}  // namespace

}  // namespace gi
