// The temporal_acceptance check (Bevy #21722): ReSTIR GI's temporal
// reuse must hold at object edges. Solari picks last frame's sample from a
// pixel permuted up to 3 px away from the reprojected one; at an edge that
// pixel often lies on another surface and is refused. Before #21722 nothing
// else was tried, so edge pixels lost their history every frame and stayed
// noisy; since, the reprojected pixel itself is the fallback
// (restir_gi.temporal_fallback point).
//
// The GI pass counts, for chain A, the edge pixels (a 4-neighbour is a miss or
// a dissimilar surface: the test reuse applies) that had an on-screen history,
// and those whose temporal reuse found it usable (GiFrameStats, compiled in
// only for this check). Over the judged frames the share reused must reach
// "min_edge_reuse".
#include <algorithm>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/json_reader.h"
#include "gpu/passes/gi_pipeline.h"
#include "checks/check_registry.h"
#include "checks/judged_frames.h"

namespace gi {
namespace {

struct EdgeFrame {
  std::uint32_t frame = 0, pixels = 0, reused = 0;
  double share() const { return pixels ? double(reused) / pixels : 1.0; }
};

class TemporalAcceptanceCheck final : public Check {
 public:
  explicit TemporalAcceptanceCheck(const CheckContext& c) {
    if (!c.gi) c.refuse("", "reads ReSTIR GI's temporal reuse: set \"gi\": true in \"mode\": \"realtime\"");
    const JsonReader r(c.scenario.file.string());
    const nlohmann::json& p = c.spec.params;
    const std::string& at = c.spec.json_path;
    if (p.contains("min_edge_reuse"))
      min_share_ = (r.number(p["min_edge_reuse"], at + "/min_edge_reuse", 0.0, 1.0), p["min_edge_reuse"].get<double>());
    judged_ = judged_frames(c, 1);
    if (!judged_ && c.frames < 2) {
      c.refuse("", "needs two frames: frame 0 has no history");
    }
  }

  CheckNeeds needs() const override {
    CheckNeeds n;
    n.reads = {FrameInput::gi_stats};
    n.gi_temporal_edges = true;
    if (judged_) n.frames = judged_;
    return n;
  }

  void observe(const FrameView& f, nlohmann::json& record) override {
    if (f.frame() == 0) return;  // no history yet
    const gpu::GiFrameStats& s = *f.gi_stats();
    const EdgeFrame e{f.frame(), s.temporal_edge_pixels, s.temporal_edge_reused};
    record["temporal_acceptance"] = {{"edge_pixels", e.pixels}, {"edge_reused", e.reused}};
    frames_.push_back(e);
  }

  CheckResult result() override {
    CheckResult c;
    c.name = "temporal_acceptance";
    c.limits = {{"min_edge_reuse", min_share_}};
    std::uint64_t pixels = 0, reused = 0;
    const EdgeFrame* worst = nullptr;
    for (const EdgeFrame& e : frames_) {
      pixels += e.pixels;
      reused += e.reused;
      if (!worst || e.share() < worst->share()) worst = &e;
    }
    const double share = pixels ? double(reused) / double(pixels) : 0.0;
    c.figures = {{"judged_frames", frames_.size()}, {"edge_pixels", pixels}, {"edge_reused", reused},
                 {"edge_reuse", share}};
    if (worst) c.figures["worst_frame"] = {{"frame", worst->frame}, {"edge_reuse", worst->share()}};
    if (pixels == 0) {
      c.verdict = Verdict::inconclusive;
      c.message = "no edge pixel with an on-screen history on any judged frame";
      return c;
    }
    c.verdict = share >= min_share_ ? Verdict::pass : Verdict::fail;
    // A failing verdict names the first frame below the limit on its own.
    if (c.verdict == Verdict::fail)
      for (const EdgeFrame& e : frames_)
        if (e.share() < min_share_) {
          c.first_failing_frame = e.frame;
          break;
        }
    c.message = fmt::format("{} of {} edge pixels with a history reused it over {} frame(s): {:.1f} % (limit {:.1f} %; "
                            "worst frame {} at {:.1f} %){}",
                            reused, pixels, frames_.size(), 100.0 * share, 100.0 * min_share_, worst->frame,
                            100.0 * worst->share(),
                            c.verdict == Verdict::pass ? "" : ": temporal reuse fails at object edges");
    return c;
  }

 private:
  std::optional<std::set<std::uint32_t>> judged_;
  double min_share_ = 0.9;
  std::vector<EdgeFrame> frames_;
};

constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "ReSTIR GI's temporal reuse at object edges (Bevy #21722): over the judged frames, the share of chain A's edge pixels (a 4-neighbour is a miss or a dissimilar surface) with an on-screen history whose temporal reuse found it usable must reach min_edge_reuse.",
  "properties": {
    "name": {
      "const": "temporal_acceptance"
    },
    "frames": {
      "type": "array",
      "items": {
        "$ref": "#/$defs/frame"
      },
      "description": "Frames judged (default: every frame from 1; frame 0 has no history)."
    },
    "min_edge_reuse": {
      "type": "number",
      "minimum": 0,
      "maximum": 1,
      "description": "Smallest allowed share of edge pixels that reuse their history (default 0.9)."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the share of chain A's edge pixels with an on-screen history whose temporal reuse found it "
    "usable",
    "the share's spread over seeds, measured: 100.0 % at every one of 10 seeds in "
    "gi_edge_reuse_cornell on an H100 (the fallback to the reprojected pixel always holds in a still "
    "view), limit 90 %",
    CheckModel::Basis::measured,
    0.00135,
    "at most 0.135 % (no seed came near the limit)"};

const RegisteredCheck<TemporalAcceptanceCheck> kRegistration{{"temporal_acceptance", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
