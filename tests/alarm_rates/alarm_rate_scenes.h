// The seed soak's table (tests/alarm_rates/alarm_rates_soak.cpp): for each
// check, a scenario of the repository whose pipeline is the fixed one, where
// the check must stay quiet. The soak runs it at several seeds and counts the
// check's alarms against the rate its model states (CheckModel,
// core/check_catalog.h). tests/check_models_test.cpp holds this table to the
// declared checks, so a new check cannot skip the soak.
#pragma once
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace gi::test {

struct AlarmRateScene {
  std::string check;
  std::string scenario;  // relative to the source tree
};

// The cheapest scene of the default suite that runs the check on a pipeline
// without its bug (luminance_range has none there: a test scene of its own).
inline const std::vector<AlarmRateScene>& alarm_rate_scenes() {
  static const std::vector<AlarmRateScene> scenes = {
      {"blend_lag", "scenarios/cache_light_response_cornell.json"},
      {"cache_integrity", "scenarios/cache_open_field.json"},
      {"cache_lifetime", "scenarios/cache_open_field.json"},
      {"cluster_ids", "scenarios/cluster_ids_cliffs_below_limit.json"},
      {"determinism", "scenarios/determinism_di_sweep.json"},
      {"finite", "scenarios/gi_corners.json"},
      {"furnace", "scenarios/furnace_bevy_main_brdf.json"},
      {"highlight_noise", "scenarios/gi_mirror_highlights.json"},
      {"jacobian", "scenarios/gi_corners.json"},
      {"light_leak", "scenarios/leak_thin_wall.json"},
      {"luminance_range", "tests/data/scenarios/good/luminance_range_steady.json"},
      {"motion", "scenarios/motion_cornell_sweep.json"},
      {"ray_budget", "scenarios/specular_ray_budget_mirror.json"},
      {"rc_energy", "scenarios/rc_lamp_and_wall.json"},
      {"rc_light_leak", "scenarios/rc_wall_leak.json"},
      {"rc_penumbra", "scenarios/rc_grating_penumbra.json"},
      {"rc_reference", "scenarios/rc_lamp_and_wall.json"},
      {"rc_ringing", "scenarios/rc_lamp_rings.json"},
      {"reference", "scenarios/gi_cornell_box.json"},
      {"shadow_lag", "scenarios/di_shadow_lag_moving_occluder.json"},
      {"spatial_acceptance", "scenarios/gi_spatial_search_cornell.json"},
      {"temporal_acceptance", "scenarios/gi_edge_reuse_cornell.json"},
      {"tile_decorrelation", "scenarios/di_many_lights.json"},
  };
  return scenes;
}

// The most alarms `runs` independent runs of a correct pipeline give at the
// per-run rate `rate`, but for a chance of at most `tail`: the smallest k
// with P(Binomial(runs, rate) > k) <= tail. More alarms than this say the
// stated rate is wrong (at that significance), not that the seeds were unlucky.
inline std::uint32_t allowed_alarms(std::uint32_t runs, double rate, double tail = 1e-3) {
  double above = 1.0;  // P(X > k), starting at k = -1
  double pk = std::pow(1.0 - rate, runs);  // P(X = 0)
  for (std::uint32_t k = 0; k <= runs; ++k) {
    above -= pk;
    if (above <= tail) return k;
    pk *= (runs - k) / double(k + 1) * rate / (1.0 - rate);
  }
  return runs;
}

}  // namespace gi::test
