// The rc_ringing check: rings at the cascades' interval
// boundaries. Cascade c sees only [start_c, start_c + range_c) from its
// probes, with 4^(c + resolution_factor) rays; a march may step past its
// interval's end, so light there is counted by two cascades, and a coarse
// cascade's rays catch a small light unevenly. Around an emitting shape in
// free space the exact answer falls off smoothly, and so the ratio of output
// to reference should be flat in the distance from it; with cascades it
// rises towards each interval boundary and drops after it. The ratio is
// taken in rings `window` px wide around the shape (`around`, default the
// canvas's only emitter), from just outside it to the nearest canvas edge;
// the figure is its swing, highest minus lowest, with the radius of the
// peak and the interval boundary nearest it. Fails when the swing exceeds
// `max_swing` plus three standard deviations of the reference's noise in
// the two rings. A uniform error of scale is rc_energy's, not this.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/rc/rc_reference.h"
#include "core/rc/rc_settings.h"
#include "checks/check_registry.h"
#include "checks/rc_frame_check_base.h"

namespace gi {
namespace {

// The shape's centre and the radius of a circle around it that holds it.
std::pair<glm::vec2, float> centre_and_extent(const CanvasShape& s) {
  if (s.type == "rect") {
    const glm::vec2 c = 0.5f * (s.points[0] + s.points[1]) + s.offset;
    return {c, 0.5f * glm::length(s.points[1] - s.points[0])};
  }
  if (s.type == "ellipse") return {s.points[0] + s.offset, std::max(s.points[1].x, s.points[1].y)};
  glm::vec2 lo = s.points[0], hi = s.points[0];
  for (glm::vec2 p : s.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return {0.5f * (lo + hi) + s.offset, 0.5f * glm::length(hi - lo) + s.half_width};
}

struct Ring {
  double output = 0, reference = 0, noise_var = 0;
  void add(const Ring& r) { output += r.output, reference += r.reference, noise_var += r.noise_var; }
  double ratio() const { return reference > 0 ? output / reference : 0.0; }
  double sigma() const { return reference > 0 ? ratio() * std::sqrt(noise_var) / reference : 0.0; }
};

class RcRingingCheck final : public RcFrameCheck {
 public:
  explicit RcRingingCheck(const CheckContext& c) : RcFrameCheck(c, "rc_ringing") {
    const nlohmann::json& p = c.spec.params;
    const std::string& at = c.spec.json_path;
    const Canvas& canvas = *c.scenario.canvas;
    if (p.contains("around")) {
      around_ = reader_.string(p["around"], at + "/around");
      const CanvasShape* s = canvas.find(around_);
      if (!s || !s->emissive) reader_.fail(at + "/around", fmt::format("expected an emitting shape, got \"{}\"", around_));
    } else {
      for (const CanvasShape& s : canvas.shapes)
        if (s.emissive) {
          if (!around_.empty()) reader_.fail(at, "expected \"around\": the canvas has more than one emitting shape");
          around_ = s.name;
        }
    }
    if (p.contains("max_swing")) max_swing_ = reader_.number(p["max_swing"], at + "/max_swing", 0.0, 100.0);
    if (p.contains("window")) window_ = reader_.uint(p["window"], at + "/window", 1, 1024);
  }

 private:
  Judgement judge(const FrameView& frame, const Image& out, const RcReference& ref) override {
    const Canvas& canvas = frame.rc_canvas();
    const auto [centre, extent] = centre_and_extent(*canvas.find(around_));
    // Rings one pixel wide, out to the nearest canvas edge.
    const float reach = std::min({centre.x, centre.y, float(canvas.width) - centre.x, float(canvas.height) - centre.y});
    const std::size_t count = std::size_t(std::max(reach, 0.0f)) + 1;
    std::vector<Ring> rings(count);
    for (std::uint32_t y = 0; y < canvas.height; ++y)
      for (std::uint32_t x = 0; x < canvas.width; ++x) {
        const std::size_t i = std::size_t(y) * canvas.width + x;
        const float r = glm::length(glm::vec2(x, y) + 0.5f - centre);
        if (!ref.free[i] || r >= float(count)) continue;
        Ring& ring = rings[std::size_t(r)];
        ring.output += rc_luminance(out.pixels[i]);
        ring.reference += rc_luminance(ref.mean.pixels[i]);
        const double d = rc_luminance(ref.half_a.pixels[i]) - rc_luminance(ref.half_b.pixels[i]);
        ring.noise_var += d * d / 4;
      }
    auto band = [&](std::size_t from, std::size_t to) {
      Ring sum;
      for (std::size_t k = from; k < to && k < count; ++k) sum.add(rings[k]);
      return sum;
    };
    Judgement j;
    nlohmann::json profile = nlohmann::json::array();
    const auto first = std::size_t(std::ceil(extent + 2.0f));
    std::size_t lo = 0, hi = 0;
    std::vector<Ring> bands;
    for (std::size_t k = first; k + window_ <= count; k += window_) {
      bands.push_back(band(k, k + window_));
      profile.push_back({{"radius", k}, {"ratio", bands.back().ratio()}});
      if (bands.back().ratio() < bands[lo].ratio()) lo = bands.size() - 1;
      if (bands.back().ratio() > bands[hi].ratio()) hi = bands.size() - 1;
    }
    if (bands.size() < 2) {
      j.verdict = Verdict::inconclusive;
      j.figures = {{"swing", 0.0}, {"around", around_}, {"profile", profile}};
      return j;
    }
    const double swing = bands[hi].ratio() - bands[lo].ratio();
    const double sigma = std::hypot(bands[hi].sigma(), bands[lo].sigma());
    // Where the ratio peaks, and the interval boundary nearest it.
    const double peak = double(first + hi * window_) + 0.5 * window_;
    double nearest = -1;
    for (float b : frame.rc_settings().interval_boundaries())
      if (nearest < 0 || std::abs(b - peak) < std::abs(nearest - peak)) nearest = b;
    j.figure = swing;
    j.figures = {{"swing", swing}, {"sigma", sigma}, {"min_ratio", bands[lo].ratio()}, {"max_ratio", bands[hi].ratio()},
                 {"peak_radius", peak}, {"nearest_boundary", nearest}, {"around", around_}, {"profile", profile}};
    j.verdict = swing > max_swing_ + 3 * sigma ? Verdict::fail : Verdict::pass;
    return j;
  }
  std::string describe(const Judgement& j, std::uint32_t frame) const override {
    if (!j.figures.contains("sigma"))
      return fmt::format("frame {}: fewer than two rings of free canvas around {}", frame, around_);
    return fmt::format("frame {}: around {} the output/reference ratio swings by {:.3f} ({:.3f} to {:.3f}), peaking "
                       "at {:.0f} px, the interval boundary nearest it {:.0f} px (limit {:.3f} + 3 x {:.4f})",
                       frame, around_, j.figures["swing"].get<double>(), j.figures["min_ratio"].get<double>(),
                       j.figures["max_ratio"].get<double>(), j.figures["peak_radius"].get<double>(),
                       j.figures["nearest_boundary"].get<double>(), max_swing_, j.figures["sigma"].get<double>());
  }
  nlohmann::json limits() const override { return {{"max_swing", max_swing_}, {"window", window_}}; }

  std::string around_;
  double max_swing_ = 0.1;
  std::uint32_t window_ = 2;
};

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the swing of the output/reference ratio over rings around an emitter",
    "the reference's standard deviation in the two rings that set the swing",
    CheckModel::Basis::derived,
    0.00135,
    "one-sided 0.135 % (max_swing + 3 sigma of a normal)"};

const RegisteredCheck<RcRingingCheck> kRegistration{{"rc_ringing",
    rc_check_schema("rc_ringing", R"j("around": {"type": "string", "description": "the emitting shape whose rings are measured (default: the only emitter)"},
    "max_swing": {"type": "number", "minimum": 0, "description": "largest difference between the highest and lowest output/reference ratio of the rings (default 0.1)"},
    "window": {"type": "integer", "minimum": 1, "description": "width of each ring, pixels (default 2)"})j"),
    kModel, {}}};

}  // namespace
}  // namespace gi
