// The radiance-cascades pipeline's settings, from its profile
// (scenarios/profiles/radiance-cascades-lesson.json, read through the profile
// table gpu/profile_keys.cpp) for one canvas size: what the passes are given
// and what summary.json reports.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/shared/rc/cascades.h"

namespace gi {

// The profile's fields (filled by the profile table, clamped to what the
// passes hold) have no value of their own here: every value is the profile's.
struct RcSettings {
  std::uint32_t width = 0, height = 0;
  bool jfa{};                               // rc.distance_field
  std::uint32_t resolution_factor{};
  float interval0{};
  std::uint32_t max_cascades{};             // rc.max_cascades, 1 .. RC_MAX_CASCADES
  std::uint32_t cascade_count{};            // rc.cascade_count, 0 .. RC_MAX_CASCADES (0: from the diagonal)
  std::uint32_t cascades_for_diagonal = 0;  // what the diagonal asks for (capped at rc.max_cascades)
  std::uint32_t cascades = 0;               // what runs: as many whose widest probe tiles the canvas
  std::uint32_t max_steps{};
  float hit_epsilon{};
  std::uint32_t mipmap_mode{};              // RC_MIPMAP_*
  std::uint32_t merge{};                    // RC_MERGE_*

  shader::RcProbe probe(std::uint32_t cascade) const {
    return shader::rc_probe_for_cascade(cascade, resolution_factor, interval0);
  }
  std::uint32_t probe_width0() const { return 1u << resolution_factor; }
  std::uint32_t mip_width() const { return (width + probe_width0() - 1) / probe_width0(); }
  std::uint32_t mip_height() const { return (height + probe_width0() - 1) / probe_width0(); }
  // Where cascade c ≥ 1's interval begins: the radii where cascades hand over.
  std::vector<float> interval_boundaries() const;
  nlohmann::json to_json() const;
};

// The lesson's cascade count: the fewest whose intervals reach `diagonal`,
// ceil(log4(1 + 3·diagonal / max(interval0, 1))), at most `max_cascades`, at least 1.
std::uint32_t rc_cascades_for_diagonal(float diagonal, float interval0, std::uint32_t max_cascades);

// The profile's values (`from_profile`: gpu/profile_keys.h rc_profile_settings)
// for a width × height canvas: its cascade count. gpu/profile_keys.h
// rc_settings(profile, width, height) does both.
RcSettings rc_settings_for_canvas(RcSettings from_profile, std::uint32_t width, std::uint32_t height);

}  // namespace gi
