// The cache_integrity check: the world cache's hash table holds
// what its queries put there, and nothing else. On each judged frame it reads
// the table back and, for every live cell, recomputes from the cell's stored
// query point and normal, with the shared maths the shaders run
// (core/shared/world_cache.h), the checksum and key the query must have had:
//   - keyed: the checksum is the stored point's at the LOD the camera gives
//     that point (or the next LOD up, under 0.19's stochastic choice). A cell
//     keyed at another size was made by a query that quantized one point at
//     another point's LOD: Bevy #21953 ("extra cells at the wrong LOD", the
//     jittered point quantized with the unjittered point's size);
//   - reachable: the slot is within max_probe_steps of that key along the
//     probe sequence, else no query can find it again (a lost cell);
//   - unique: no two copies of a cell on one key chain both refreshed to the
//     full lifetime this frame (copies behind a re-inserted cell go stale, as
//     in Bevy, and are only counted);
//   - counted: the live cells in the table are the statistics pass's count.
// The LOD depends on the camera position of the query that made the cell,
// so "keyed" and "reachable" are judged only while the camera has not moved
// (turning is fine); frames after a move are reported as not testable.
#include <algorithm>
#include <map>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/scene.h"
#include "core/shared/world_cache.h"
#include "gpu/passes/world_cache.h"
#include "checks/cache_lifetime_check.h"
#include "checks/check_registry.h"

namespace gi {
namespace {

using shader::uvec3;
using shader::vec3;

struct FrameFigures {
  std::uint32_t frame = 0;
  std::uint32_t live = 0, miskeyed = 0, unreachable = 0, duplicates = 0, stale_copies = 0;
  std::uint32_t stats_live = 0;
  bool testable = true;  // the camera had not moved
};

// The normal's key, allowing for the octahedral packing of stored normals:
// a component within 1e-3 of a step may have been on either side of it.
std::vector<uvec3> normal_keys(const vec3& n, float scale) {
  std::vector<uvec3> keys;
  for (float dx : {0.0f, -1e-3f, 1e-3f})
    for (float dy : {0.0f, -1e-3f, 1e-3f})
      for (float dz : {0.0f, -1e-3f, 1e-3f}) {
        const uvec3 k = shader::world_cache_quantize_normal(n + vec3(dx, dy, dz), scale);
        if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
      }
  return keys;
}

FrameFigures judge(std::uint32_t frame, const CacheCells& cells, const vec3& eye, bool testable) {
  const gpu::WorldCacheSettings& s = *cells.settings;
  FrameFigures f;
  f.frame = frame;
  f.testable = testable;
  // (key, checksum) → the lives of the live cells on that chain.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> chains;
  auto reachable = [&](std::uint32_t key, std::uint32_t slot) {
    for (std::uint32_t step = 0, k = key; step < s.max_probe_steps; ++step) {
      if (k == slot) return true;
      k = shader::world_cache_next_key(k, s.cells, s.linear_probing);
    }
    return false;
  };
  for (std::uint32_t i = 0; i < cells.checksums.size(); ++i) {
    if (cells.life[i] == 0 || cells.checksums[i] == shader::WORLD_CACHE_EMPTY_CELL) continue;
    ++f.live;
    if (!testable) continue;
    const vec3 p(cells.positions[i]), n(cells.normals[i]);
    // The sizes a query at this point can have used: its LOD; under 0.19 the
    // next LOD up (stochastic choice) and the base cell (ReSTIR GI's
    // first-bounce rule for rays shorter than their cell).
    const float lod_size = shader::world_cache_cell_size(p, eye, s.cell_size_base, s.lod_scale);
    std::vector<float> sizes = {lod_size};
    if (s.stochastic_lod) sizes.push_back(2.0f * lod_size);
    if (s.first_bounce_leak_rule && lod_size != s.cell_size_base) sizes.push_back(s.cell_size_base);
    // Solari's checksum is weak over small quantized coordinates (README,
    // "World cache"): a candidate explains the cell only if its checksum
    // matches and the slot is on its key's probe sequence.
    bool checksum_matched = false;
    std::optional<std::uint32_t> key;
    for (float size : sizes)
      for (const uvec3& qn : normal_keys(n, s.normal_key_scale)) {
        const uvec3 qp = shader::world_cache_quantize_position(p, size);
        if (key || shader::world_cache_checksum(qp, qn) != cells.checksums[i]) continue;
        checksum_matched = true;
        const std::uint32_t k = shader::world_cache_key(qp, qn, s.cells);
        if (reachable(k, i)) key = k;
      }
    if (!checksum_matched) {
      ++f.miskeyed;
    } else if (!key) {
      ++f.unreachable;
    } else {
      chains[{*key, cells.checksums[i]}].push_back(cells.life[i]);
    }
  }
  // Two copies of a cell on one chain arise legitimately once a cell ahead
  // of one has died: the next query finds the empty slot first and inserts
  // again there, and the copy behind goes stale (open addressing without
  // tombstones, as in Bevy). Every query stops at the first copy, so only
  // one copy can have been refreshed to the full lifetime this frame: two
  // at the full lifetime are a duplication.
  for (const auto& [chain, lives] : chains) {
    if (lives.size() < 2) continue;
    f.stale_copies += static_cast<std::uint32_t>(lives.size() - 1);
    const auto fresh = std::count(lives.begin(), lives.end(), s.lifetime);
    if (fresh > 1) f.duplicates += static_cast<std::uint32_t>(fresh - 1);
  }
  return f;
}

class CacheIntegrityPlugin final : public Check {
 public:
  explicit CacheIntegrityPlugin(const CheckContext& c) {
    require_world_cache(c);
    const std::string file = c.scenario.file.string();
    if (c.spec.params.contains("frames")) {
      const nlohmann::json& f = c.spec.params["frames"];
      for (const auto& v : f) {
        if (!v.is_number_unsigned() || v.get<std::uint32_t>() >= c.frames)
          throw InputError(file, c.spec.json_path + "/frames",
                           fmt::format("expected frame numbers below the frame count {}", c.frames));
        judged_.insert(v.get<std::uint32_t>());
      }
    } else {
      judged_.insert(c.frames - 1);
    }
  }
  // Every frame, for the camera position (a vec3); the table only on judged frames.
  CheckNeeds needs() const override { return {.reads = {FrameInput::cache_stats, FrameInput::cache_cells}}; }
  void observe(const FrameView& v, nlohmann::json& record) override {
    const glm::vec3 eye = v.scene().camera.position;
    if (!first_eye_) first_eye_ = eye;
    moved_ = moved_ || eye != *first_eye_;
    if (!judged_.count(v.frame())) return;
    FrameFigures f = judge(v.frame(), v.cache_cells(), vec3(eye), !moved_);
    f.stats_live = v.cache_stats()->live_cells;
    record["cache_integrity"] = {{"live", f.live},
                                 {"miskeyed", f.miskeyed},
                                 {"unreachable", f.unreachable},
                                 {"duplicates", f.duplicates},
                                 {"stale_copies", f.stale_copies},
                                 {"testable", f.testable}};
    judged_figures_.push_back(f);
  }
  CheckResult result() override;

 private:
  std::set<std::uint32_t> judged_;
  std::optional<glm::vec3> first_eye_;
  bool moved_ = false;
  std::vector<FrameFigures> judged_figures_;
};

CheckResult CacheIntegrityPlugin::result() {
  CheckResult c;
  c.name = "cache_integrity";
  c.limits = {{"miskeyed", 0}, {"unreachable", 0}, {"duplicates", 0}};
  nlohmann::json frames = nlohmann::json::array();
  std::vector<std::string> failures;
  std::size_t tested = 0;
  for (const FrameFigures& f : judged_figures_) {
    frames.push_back({{"frame", f.frame}, {"live", f.live}, {"stats_live", f.stats_live}, {"miskeyed", f.miskeyed},
                      {"unreachable", f.unreachable}, {"duplicates", f.duplicates},
                      {"stale_copies", f.stale_copies}, {"testable", f.testable}});
    std::vector<std::string> bad;
    if (f.live != f.stats_live) bad.push_back(fmt::format("{} live cells in the table, {} counted", f.live, f.stats_live));
    if (f.testable) {
      ++tested;
      if (f.miskeyed) bad.push_back(fmt::format("{} of {} cells keyed at an LOD their point does not have", f.miskeyed, f.live));
      if (f.unreachable) bad.push_back(fmt::format("{} cells beyond their key's probe steps (lost)", f.unreachable));
      if (f.duplicates) bad.push_back(fmt::format("{} duplicated cells", f.duplicates));
    }
    if (!bad.empty()) {
      if (!c.first_failing_frame) c.first_failing_frame = f.frame;
      std::string m = fmt::format("frame {}: ", f.frame);
      for (std::size_t i = 0; i < bad.size(); ++i) m += (i ? ", " : "") + bad[i];
      failures.push_back(m);
    }
  }
  c.figures = {{"judged_frames", frames}, {"tested_frames", tested}};
  if (!failures.empty()) {
    c.verdict = Verdict::fail;
    for (std::size_t i = 0; i < failures.size(); ++i) c.message += (i ? "; " : "") + failures[i];
  } else if (tested == 0) {
    c.verdict = Verdict::inconclusive;
    c.message = "the camera moved before every judged frame: the cells' LOD cannot be recomputed (counts agree)";
  } else {
    c.verdict = Verdict::pass;
    std::uint32_t live = judged_figures_.empty() ? 0 : judged_figures_.back().live;
    c.message = fmt::format("{} judged frame(s): every live cell keyed at its point's LOD, reachable, unique; "
                            "{} live cells at the last", tested, live);
  }
  return c;
}

constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "World-cache table integrity: on the judged frames every live cell's checksum is its stored query point's at the LOD the camera gives it (keyed), its slot is within max_probe_steps of its key (reachable), no two live cells share a key chain and checksum (unique), and the table's live count is the statistics' count. Keyed and reachable need a camera that has not moved (turning is fine).",
  "properties": {
    "name": {
      "const": "cache_integrity"
    },
    "frames": {
      "type": "array",
      "items": {
        "$ref": "#/$defs/frame"
      },
      "description": "Frames whose table is read back and judged (default: the last frame)."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "for every live world-cache cell, whether its checksum, probe position and uniqueness follow from"
    " its stored query point with the shaders' own maths",
    "none: an exact recomputation; which cells exist moves with the seed, but each must satisfy the "
    "rules",
    CheckModel::Basis::exact,
    0.0,
    "0 on frames it judges (the camera has not moved since the cell was made; others are reported as "
    "not testable)"};

const RegisteredCheck<CacheIntegrityPlugin> kRegistration{{"cache_integrity", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
