// The cache_lifetime check (docs/design.md §6): no immortal cells, bounded occupancy.
// Per frame it reads the world cache's statistics (integer atomics over every
// cell, gpu/shaders/world_cache_stats.comp, with root-frame instrumentation):
// it passes when every live cell has frame − root_frame ≤ lifetime + 1,
// 0 ≤ life ≤ lifetime, dead cells are empty, and — with "occupancy_frames" —
// the active count at the second frame is within "occupancy_ratio" of the
// first (the level returns after a camera sweep comes back).
#pragma once
#include <array>
#include <cstdint>
#include <optional>

#include "core/scenario.h"
#include "gpu/passes/world_cache.h"
#include "checks/check_result.h"

namespace gi {

struct CacheLifetimeParams {
  std::uint32_t lifetime = 30;  // the profile's world_cache.lifetime
  std::optional<std::array<std::uint32_t, 2>> occupancy_frames;  // [before the sweep, after it came back]
  double occupancy_ratio = 1.25;  // active(after) ≤ ratio · active(before)
};

// InputError naming the check's JSON path for bad params.
CacheLifetimeParams cache_lifetime_params(const CheckSpec& spec, const Scenario& scenario, std::uint32_t lifetime,
                                          std::uint32_t frames);

class CacheLifetimeCheck {
 public:
  explicit CacheLifetimeCheck(const CacheLifetimeParams& params) : params_(params) {}
  void record_frame(std::uint32_t frame, const gpu::WorldCacheFrameStats& stats);
  CheckResult result() const;
  std::uint32_t peak_active_cells() const { return peak_active_; }

 private:
  CacheLifetimeParams params_;
  std::uint32_t frames_ = 0;
  std::uint32_t peak_active_ = 0, peak_live_ = 0;
  std::uint32_t max_over_age_ = 0, oldest_age_ = 0, max_life_out_of_range_ = 0, max_dead_not_empty_ = 0;
  std::optional<std::uint32_t> first_over_age_, first_life_bad_, first_dead_bad_;
  std::uint32_t over_age_at_first_ = 0, oldest_at_first_ = 0;
  std::optional<std::uint32_t> active_before_, active_after_;
};

struct CheckContext;
// InputError unless the run feeds the world cache (realtime, with GI's
// queries or the debug view): what cache_lifetime and blend_lag read.
void require_world_cache(const CheckContext& context);

}  // namespace gi
