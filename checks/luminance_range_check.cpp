// The `luminance_range` check: the output's mean luminance stays within
// [min, max] on the judged frames. The cheapest guard a nightly has against a
// frame that went black (lost lights, a shadow test that always hits, a
// zeroed resolve) or blew up (fireflies, a runaway history): it needs no
// reference and reads one number the frame loop already has. The reference
// check judges how close an image is; this one only that it is plausible.
// Fails at the first frame outside, and names it.
#include <limits>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/json_reader.h"
#include "checks/check_registry.h"

namespace gi {
namespace {

class LuminanceRangeCheck final : public Check {
 public:
  explicit LuminanceRangeCheck(const CheckContext& c) {
    const JsonReader r(c.scenario.file.string());
    const nlohmann::json& p = c.spec.params;
    if (p.contains("min")) min_ = r.number(p["min"], c.spec.json_path + "/min", 0.0, 1e9);
    if (p.contains("max")) max_ = r.number(p["max"], c.spec.json_path + "/max", 0.0, 1e9);
    if (min_ > max_) r.fail(c.spec.json_path + "/max", fmt::format("expected max ≥ min ({})", min_));
    if (p.contains("frames")) {
      const nlohmann::json& f = r.array(p["frames"], c.spec.json_path + "/frames", 1);
      std::set<std::uint32_t> frames;
      for (std::size_t i = 0; i < f.size(); ++i)
        frames.insert(r.uint(f[i], JsonReader::at(c.spec.json_path + "/frames", i), 0, c.frames - 1));
      frames_ = frames;
    }
  }

  CheckNeeds needs() const override {
    CheckNeeds n;
    n.reads = {FrameInput::output};
    n.frames = frames_;
    return n;
  }

  void observe(const FrameView& f, nlohmann::json&) override {
    const double y = f.output_luminance();
    ++judged_;
    lowest_ = std::min(lowest_, y);
    highest_ = std::max(highest_, y);
    // NaN is outside every range (the finite check says where it came from).
    if (!(y >= min_ && y <= max_)) {
      ++outside_;
      if (!first_) first_ = f.frame();
    }
  }

  nlohmann::json saved_state() const override {
    return {{"judged", judged_}, {"outside", outside_}, {"lowest", lowest_}, {"highest", highest_},
            {"first_frame", first_ ? nlohmann::json(*first_) : nlohmann::json()}};
  }
  void restore_state(const nlohmann::json& s) override {
    judged_ = s.value("judged", std::uint64_t{0});
    outside_ = s.value("outside", std::uint64_t{0});
    lowest_ = s.value("lowest", std::numeric_limits<double>::infinity());
    highest_ = s.value("highest", -std::numeric_limits<double>::infinity());
    if (s.contains("first_frame") && s["first_frame"].is_number_unsigned()) first_ = s["first_frame"].get<std::uint32_t>();
  }

  CheckResult result() override {
    CheckResult c;
    c.name = "luminance_range";
    c.limits = {{"min", min_}, {"max", max_}};
    c.figures = {{"frames_judged", judged_}, {"frames_outside", outside_}};
    if (judged_ > 0) c.figures.update({{"lowest_mean_luminance", lowest_}, {"highest_mean_luminance", highest_}});
    c.first_failing_frame = first_;
    if (judged_ == 0) {
      c.verdict = Verdict::inconclusive;
      c.message = "no frame judged (the run ended before the check's frames)";
    } else if (first_) {
      c.verdict = Verdict::fail;
      c.message = fmt::format("mean luminance outside [{}, {}] on {} of {} frames, first at frame {}", min_, max_,
                              outside_, judged_, *first_);
    } else {
      c.verdict = Verdict::pass;
      c.message = fmt::format("mean luminance within [{}, {}] on {} frames ({:.4g} to {:.4g})", min_, max_, judged_,
                              lowest_, highest_);
    }
    return c;
  }

 private:
  double min_ = 0.0, max_ = 1e9;
  std::optional<std::set<std::uint32_t>> frames_;
  std::uint64_t judged_ = 0, outside_ = 0;
  double lowest_ = std::numeric_limits<double>::infinity(), highest_ = -std::numeric_limits<double>::infinity();
  std::optional<std::uint32_t> first_;
};

// This check's parameters as scenarios/schema.json states them
// ($defs/check_luminance_range, which `giharness schema` writes from here);
// the parser accepts exactly these keys.
constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "The output's mean luminance stays within [min, max] on the judged frames: a guard against a frame that went black or blew up, with no reference. Fails at the first frame outside.",
  "properties": {
    "name": {
      "const": "luminance_range"
    },
    "min": {
      "type": "number",
      "minimum": 0,
      "maximum": 1000000000,
      "description": "Lowest allowed mean luminance of the output (default 0)."
    },
    "max": {
      "type": "number",
      "minimum": 0,
      "maximum": 1000000000,
      "description": "Highest allowed mean luminance of the output (default 1e9); at least min."
    },
    "frames": {
      "type": "array",
      "minItems": 1,
      "items": {
        "type": "integer",
        "minimum": 0
      },
      "description": "The frames judged, each below the frame count (default: every frame)."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the output's mean luminance on each judged frame",
    "none modelled: min and max are the scenario's plausibility bounds, set far outside the "
    "frame-to-frame spread of its fixed pipeline",
    CheckModel::Basis::measured,
    0.00135,
    "at most 0.135 % where the bounds are at least 3 sd of the per-frame mean from the fixed "
    "pipeline's level"};

const RegisteredCheck<LuminanceRangeCheck> kRegistration{{"luminance_range", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
