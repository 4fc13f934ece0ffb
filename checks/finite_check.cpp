// The `finite` check (docs/design.md §6): no NaN or inf anywhere the run can see one:
// the output's pixels every frame, the reference mode's samples, and with GI
// its reservoirs and GI/specular outputs (integer counters the GI passes keep,
// gpu/passes/gi_pipeline.h). Fails at the first frame with any, and names it.
#include <fmt/format.h>

#include "gpu/passes/gi_pipeline.h"
#include "checks/check_registry.h"

namespace gi {
namespace {

class FiniteCheck final : public Check {
 public:
  explicit FiniteCheck(const CheckContext& c) : realtime_(c.realtime), has_gi_(c.gi) {}

  CheckNeeds needs() const override {
    CheckNeeds n;
    n.reads = {FrameInput::output};
    if (has_gi_) n.reads.insert(FrameInput::gi_stats);
    if (!realtime_) n.reads.insert(FrameInput::nonfinite_samples);
    return n;
  }

  void observe(const FrameView& f, nlohmann::json&) override {
    pixels_ += f.nonfinite_pixels();
    std::uint64_t samples = 0;
    if (!realtime_) {
      // The renderer counts since the accumulation window began: a drop
      // means a new window, whose predecessor's count is kept.
      samples = f.nonfinite_samples();
      if (samples < window_samples_) samples_before_ += window_samples_;
      window_samples_ = samples;
    }
    std::uint64_t gi = 0;
    if (has_gi_) gi = std::uint64_t(f.gi_stats()->nonfinite_reservoirs) + f.gi_stats()->nonfinite_output;
    gi_values_ += gi;
    if ((f.nonfinite_pixels() > 0 || samples > 0 || gi > 0) && !first_) first_ = f.frame();
  }

  nlohmann::json saved_state() const override {
    return {{"pixels", pixels_}, {"gi", gi_values_}, {"first_frame", first_ ? nlohmann::json(*first_) : nlohmann::json()}};
  }
  void restore_state(const nlohmann::json& s) override {
    pixels_ = s.value("pixels", std::uint64_t{0});
    gi_values_ = s.value("gi", std::uint64_t{0});
    if (s.contains("first_frame") && s["first_frame"].is_number_unsigned()) first_ = s["first_frame"].get<std::uint32_t>();
  }

  CheckResult result() override {
    CheckResult c;
    c.name = "finite";
    c.figures = {{"nonfinite_samples", samples_before_ + window_samples_}, {"nonfinite_pixels", pixels_}};
    if (has_gi_) c.figures["nonfinite_gi_reservoirs_and_output"] = gi_values_;
    c.limits = {{"nonfinite", 0}};
    c.first_failing_frame = first_;
    c.verdict = first_ ? Verdict::fail : Verdict::pass;
    c.message = first_ ? fmt::format("non-finite values from frame {}", *first_)
                       : "no NaN or inf in any sample or output pixel";
    return c;
  }

 private:
  bool realtime_, has_gi_;
  std::uint64_t pixels_ = 0, gi_values_ = 0, samples_before_ = 0, window_samples_ = 0;
  std::optional<std::uint32_t> first_;
};

// This check's parameters as scenarios/schema.json states them ($defs/check_finite,
// which `giharness schema` writes from here); the parser accepts exactly
// these keys.
constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "properties": {
    "name": {
      "const": "finite"
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "whether any output pixel, reference-mode sample, GI reservoir or GI/specular output is NaN or "
    "inf (integer counters kept on the GPU)",
    "none: a count, and a correct pipeline produces no non-finite value at any seed",
    CheckModel::Basis::exact,
    0.0,
    "0: any non-finite value is a finding, never noise"};

const RegisteredCheck<FiniteCheck> kRegistration{{"finite", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
