// What the radiance-cascades checks (rc_*.cpp) share: each judges
// chosen frames ("frames", default the last) by comparing the pipeline's
// output with the 2D path tracer's reference of the same canvas
// (core/rc/rc_reference.h) over pixels outside every shape, where the output
// is the cascades' radiance alone. A check gives one figure per frame with a
// pass, fail or inconclusive judgement; the worst frame decides, and the
// first failing frame's images (output, reference, difference) are its evidence.
#pragma once
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "core/json_reader.h"
#include "core/rc/rc_reference.h"
#include "checks/check.h"

namespace gi {

// A rectangle of pixels, [x0, x1) × [y0, y1), within the canvas.
struct RcRegion {
  std::uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool contains(std::uint32_t x, std::uint32_t y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
  nlohmann::json to_json() const { return {x0, y0, x1, y1}; }
  RcComparison compare(const Image& image, const RcReference& ref) const { return rc_compare(image, ref, x0, y0, x1, y1); }
};

class RcFrameCheck : public Check {
 public:
  CheckNeeds needs() const override;
  void observe(const FrameView& frame, nlohmann::json& record) override;
  CheckResult result() override;

 protected:
  struct Judgement {
    Verdict verdict = Verdict::pass;
    double figure = 0.0;        // the value held to the limit
    nlohmann::json figures;     // everything measured on the frame
  };
  // Reads "frames" and the keys every rc check has; `name` is the check's.
  RcFrameCheck(const CheckContext& c, std::string name);
  virtual Judgement judge(const FrameView& frame, const Image& output, const RcReference& reference) = 0;
  // The one line a person reads first, from the decisive frame's figures.
  virtual std::string describe(const Judgement& decisive, std::uint32_t frame) const = 0;
  virtual nlohmann::json limits() const = 0;
  // Larger is worse (false: smaller is worse).
  virtual bool larger_is_worse() const { return true; }

  RcRegion region(const std::string& key) const;  // the param's rectangle, or the whole canvas
  RcRegion required_region(const std::string& key, const std::string& what) const;  // InputError without it

  // The context's long-lived parts (the context itself is a temporary).
  const Scenario& scenario_;
  const CheckSpec& spec_;
  const RunOptions& options_;
  const JsonReader reader_;
  std::string name_;

 private:
  std::set<std::uint32_t> frames_;
  std::vector<std::pair<std::uint32_t, Judgement>> judged_;
  bool evidence_written_ = false;
  std::vector<std::string> evidence_;
};

// The JSON Schema of an rc check: "name", "frames" and `extra` properties.
std::string rc_check_schema(const std::string& name, const std::string& extra_properties);

}  // namespace gi
