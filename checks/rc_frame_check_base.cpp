#include "checks/rc_frame_check_base.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/exr_io.h"
#include "core/rc/rc_reference.h"
#include "core/run_options.h"

namespace gi {

RcFrameCheck::RcFrameCheck(const CheckContext& c, std::string name)
    : scenario_(c.scenario), spec_(c.spec), options_(c.options), reader_(c.scenario.file.string()), name_(std::move(name)) {
  const nlohmann::json& p = c.spec.params;
  if (p.contains("frames")) {
    const nlohmann::json& f = reader_.array(p["frames"], c.spec.json_path + "/frames", 1);
    // Frames past a shorter run (--frames) are left out, as a replay leaves out those before it.
    for (std::size_t i = 0; i < f.size(); ++i) {
      const std::uint32_t frame =
          reader_.uint(f[i], JsonReader::at(c.spec.json_path + "/frames", i), 0, c.scenario.frames - 1);
      if (frame < c.frames) frames_.insert(frame);
    }
  } else {
    frames_.insert(c.frames - 1);
  }
}

CheckNeeds RcFrameCheck::needs() const {
  return {.reads = {FrameInput::output_image, FrameInput::rc_canvas, FrameInput::rc_reference}, .frames = frames_};
}

RcRegion RcFrameCheck::region(const std::string& key) const {
  const Scenario& s = scenario_;
  RcRegion r{0, 0, s.resolution[0], s.resolution[1]};
  const nlohmann::json& p = spec_.params;
  if (!p.contains(key)) return r;
  const std::string at = spec_.json_path + "/" + key;
  if (!p[key].is_array() || p[key].size() != 4) reader_.fail(at, "expected [x0, y0, x1, y1] in pixels");
  r.x0 = reader_.uint(p[key][0], at + "/0", 0, s.resolution[0] - 1);
  r.y0 = reader_.uint(p[key][1], at + "/1", 0, s.resolution[1] - 1);
  r.x1 = reader_.uint(p[key][2], at + "/2", r.x0 + 1, s.resolution[0]);
  r.y1 = reader_.uint(p[key][3], at + "/3", r.y0 + 1, s.resolution[1]);
  return r;
}

RcRegion RcFrameCheck::required_region(const std::string& key, const std::string& what) const {
  if (!spec_.params.contains(key))
    reader_.fail(spec_.json_path + "/" + key, "missing required key \"" + key + "\" (" + what + ")");
  return region(key);
}

void RcFrameCheck::observe(const FrameView& frame, nlohmann::json& record) {
  const Image& output = frame.output();
  const RcReference& reference = frame.rc_reference();
  Judgement j = judge(frame, output, reference);
  record[name_] = j.figures;
  if (j.verdict != Verdict::pass && !evidence_written_) {
    // The first failing frame's images, for a person to open.
    Image difference = difference_images(output, reference.mean);
    const std::string file = fmt::format("{}_frame_{:05}.exr", name_, frame.frame());
    write_exr(options_.out_dir / file, {{"", &output}, {"reference", &reference.mean}, {"difference", &difference}});
    evidence_.push_back(file);
    evidence_written_ = true;
  }
  judged_.emplace_back(frame.frame(), std::move(j));
}

CheckResult RcFrameCheck::result() {
  CheckResult r;
  r.name = name_;
  r.limits = limits();
  r.evidence = evidence_;
  if (judged_.empty()) {
    r.verdict = Verdict::inconclusive;
    r.message = "no frame was judged";
    return r;
  }
  nlohmann::json per_frame = nlohmann::json::array();
  std::size_t decisive = 0;
  bool failed = false, inconclusive = false;
  for (std::size_t i = 0; i < judged_.size(); ++i) {
    const auto& [frame, j] = judged_[i];
    nlohmann::json f = j.figures;
    f["frame"] = frame;
    f["verdict"] = to_string(j.verdict);
    per_frame.push_back(f);
    if (j.verdict == Verdict::fail && !failed) {
      failed = true;
      r.first_failing_frame = frame;
    }
    inconclusive |= j.verdict == Verdict::inconclusive;
    const double a = j.figure, b = judged_[decisive].second.figure;
    if (larger_is_worse() ? a > b : a < b) decisive = i;
  }
  r.verdict = failed ? Verdict::fail : inconclusive ? Verdict::inconclusive : Verdict::pass;
  r.figures = judged_[decisive].second.figures;
  r.figures["frame"] = judged_[decisive].first;
  r.figures["frames"] = per_frame;
  r.message = describe(judged_[decisive].second, judged_[decisive].first);
  return r;
}

std::string rc_check_schema(const std::string& name, const std::string& extra) {
  return fmt::format(R"json({{
  "type": "object",
  "additionalProperties": false,
  "properties": {{
    "name": {{"const": "{}"}},
    "frames": {{"type": "array", "minItems": 1, "items": {{"type": "integer", "minimum": 0}},
               "description": "the frames judged (default: the last)"}}{}{}
  }}
}})json",
                     name, extra.empty() ? "" : ",\n    ", extra);
}

}  // namespace gi
