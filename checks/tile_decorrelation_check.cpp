// The tile_decorrelation check: each frame's light tiles are a
// fresh draw, not last frame's pools moved about. On each judged frame f it
// compares the light-tile samples of frame f with those of frame f − 1 (both
// read back, chain A only, on those two frames alone): for every tile of
// frame f, the largest share of its samples found in any one tile of frame
// f − 1 (a sample is its light, triangle, random seed and validity, so an
// equal sample is the same draw). Independent draws share almost nothing;
// Bevy before #24670 seeded a pool with tile + frame, so tile t at frame f
// was tile t + 1 of frame f − 1 sample for sample, and the light tiles
// "scrolled". Fails when the largest share exceeds "max_overlap".
#include <algorithm>
#include <array>
#include <map>

#include <fmt/format.h>

#include "core/errors.h"
#include "checks/check_registry.h"

namespace gi {
namespace {

using Sample = std::array<std::uint32_t, 4>;

struct Overlap {
  std::uint32_t frame = 0;
  double max_share = 0.0;   // the largest share of one tile's samples found in one tile of the frame before
  double mean_share = 0.0;  // over the tiles
  std::uint32_t tile = 0;   // the tile with the largest share
};

// For each tile of `now`, the largest share of its (valid) samples that
// one tile of `before` holds too.
Overlap compare(std::uint32_t frame, const std::vector<Sample>& before, const std::vector<Sample>& now,
                std::uint32_t per_tile) {
  std::map<Sample, std::vector<std::uint32_t>> where;  // a sample of `before` → its tiles
  for (std::uint32_t i = 0; i < before.size(); ++i)
    if (before[i][3] != 0) where[before[i]].push_back(i / per_tile);
  Overlap o;
  o.frame = frame;
  const std::uint32_t tiles = static_cast<std::uint32_t>(now.size() / per_tile);
  for (std::uint32_t t = 0; t < tiles; ++t) {
    std::map<std::uint32_t, std::uint32_t> shared;  // tile of `before` → samples in common
    std::uint32_t valid = 0;
    for (std::uint32_t k = 0; k < per_tile; ++k) {
      const Sample& s = now[std::size_t(t) * per_tile + k];
      if (s[3] == 0) continue;
      ++valid;
      auto it = where.find(s);
      if (it == where.end()) continue;
      for (std::uint32_t b : it->second) ++shared[b];
    }
    std::uint32_t most = 0;
    for (const auto& [b, n] : shared) most = std::max(most, n);
    const double share = valid ? double(most) / valid : 0.0;
    o.mean_share += share / tiles;
    if (share > o.max_share) {
      o.max_share = share;
      o.tile = t;
    }
  }
  return o;
}

class TileDecorrelationPlugin final : public Check {
 public:
  explicit TileDecorrelationPlugin(const CheckContext& c) {
    if (!c.realtime) c.refuse("", "reads the light tiles, which run in \"mode\": \"realtime\" only");
    const std::string file = c.scenario.file.string();
    const nlohmann::json& j = c.spec.params;
    if (j.contains("frames")) {
      for (const auto& v : j["frames"]) {
        if (!v.is_number_unsigned() || v.get<std::uint32_t>() == 0 || v.get<std::uint32_t>() >= c.frames)
          throw InputError(file, c.spec.json_path + "/frames",
                           fmt::format("expected frame numbers from 1 to {} (each is compared with the frame before)",
                                       c.frames - 1));
        judged_.insert(v.get<std::uint32_t>());
      }
    } else {
      if (c.frames < 2) c.refuse("", "needs two frames to compare");
      judged_.insert(c.frames - 1);
    }
    if (j.contains("max_overlap")) {
      if (!j["max_overlap"].is_number() || j["max_overlap"].get<double>() < 0.0 || j["max_overlap"].get<double>() > 1.0)
        throw InputError(file, c.spec.json_path + "/max_overlap", "expected a share from 0 to 1");
      max_overlap_ = j["max_overlap"].get<double>();
    }
  }
  CheckNeeds needs() const override {
    std::set<std::uint32_t> frames;
    for (std::uint32_t f : judged_) frames.insert({f - 1, f});
    return {.reads = {FrameInput::light_tiles}, .frames = frames};
  }
  void observe(const FrameView& v, nlohmann::json& record) override {
    std::uint32_t per_tile = 0;
    std::vector<Sample> now = v.light_tile_samples(per_tile);
    if (judged_.count(v.frame()) && previous_frame_ && *previous_frame_ + 1 == v.frame()) {
      const Overlap o = compare(v.frame(), previous_, now, per_tile);
      record["tile_decorrelation"] = {{"max_share", o.max_share}, {"mean_share", o.mean_share}};
      results_.push_back(o);
    }
    previous_ = std::move(now);
    previous_frame_ = v.frame();
  }
  CheckResult result() override;

 private:
  std::set<std::uint32_t> judged_;
  double max_overlap_ = 0.05;
  std::vector<Sample> previous_;
  std::optional<std::uint32_t> previous_frame_;
  std::vector<Overlap> results_;
};

CheckResult TileDecorrelationPlugin::result() {
  CheckResult c;
  c.name = "tile_decorrelation";
  c.limits = {{"max_overlap", max_overlap_}};
  nlohmann::json frames = nlohmann::json::array();
  double worst = 0.0;
  for (const Overlap& o : results_) {
    frames.push_back({{"frame", o.frame}, {"max_share", o.max_share}, {"mean_share", o.mean_share}, {"tile", o.tile}});
    if (o.max_share > max_overlap_ && !c.first_failing_frame) c.first_failing_frame = o.frame;
    worst = std::max(worst, o.max_share);
  }
  c.figures = {{"judged_frames", frames}, {"max_share", worst}};
  if (results_.empty()) {
    c.verdict = Verdict::inconclusive;
    c.message = "no judged frame had its frame before recorded";
  } else if (c.first_failing_frame) {
    const Overlap& o = *std::find_if(results_.begin(), results_.end(),
                                     [&](const Overlap& r) { return r.frame == *c.first_failing_frame; });
    c.verdict = Verdict::fail;
    c.message = fmt::format("frame {}: tile {} shares {:.1f} % of its samples with one tile of frame {} (limit {:.1f} %; "
                            "mean over tiles {:.1f} %): the tiles repeat last frame's pools",
                            o.frame, o.tile, 100.0 * o.max_share, o.frame - 1, 100.0 * max_overlap_,
                            100.0 * o.mean_share);
  } else {
    c.verdict = Verdict::pass;
    c.message = fmt::format("{} judged frame(s): no tile shares more than {:.2f} % of its samples with a tile of the "
                            "frame before (limit {:.1f} %)",
                            results_.size(), 100.0 * worst, 100.0 * max_overlap_);
  }
  return c;
}

constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "Light tiles drawn afresh each frame (Bevy #24670): on each judged frame f, no tile shares more than max_overlap of its samples with any one tile of frame f - 1.",
  "properties": {
    "name": {
      "const": "tile_decorrelation"
    },
    "frames": {
      "type": "array",
      "items": {
        "$ref": "#/$defs/frame"
      },
      "description": "Frames compared with the frame before (default: the last frame); frame 0 has none."
    },
    "max_overlap": {
      "type": "number",
      "minimum": 0,
      "maximum": 1,
      "description": "Largest allowed share of one tile's samples found in one tile of the frame before (default 0.05; independent draws share none)."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the largest share of one light tile's samples (light, triangle, random seed, validity) found in "
    "any one tile of the frame before",
    "independent draws repeat a sample only if its 32-bit random seed repeats with the same light and"
    " triangle",
    CheckModel::Basis::derived,
    1e-12,
    "below 1e-12: max_overlap is at least 5 % of a tile, and a chance repetition of that many 32-bit "
    "seeds has a negligible probability (0.00 % overlap at 10 seeds)"};

const RegisteredCheck<TileDecorrelationPlugin> kRegistration{{"tile_decorrelation", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
