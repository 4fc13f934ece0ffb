// The radiance-cascades pipeline's settings, read from its profile
// (scenarios/profiles/radiance-cascades-lesson.json) for one canvas size:
// what the passes are given and what summary.json reports.
#pragma once
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/shared/rc/cascades.h"

namespace gi {

struct Profile;

struct RcSettings {
  std::uint32_t width = 0, height = 0;
  bool jfa = false;                        // rc.distance_field
  std::uint32_t resolution_factor = 1;
  float interval0 = 2.0f;
  std::uint32_t cascades_for_diagonal = 0;  // what the diagonal asks for (capped at rc.max_cascades)
  std::uint32_t cascades = 0;               // what runs: as many whose widest probe tiles the canvas
  std::uint32_t max_steps = 32;
  float hit_epsilon = 4.88e-4f;
  std::uint32_t mipmap_mode = shader::RC_MIPMAP_PROBE_WIDTH_X2;
  std::uint32_t merge = shader::RC_MERGE_LESSON;

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

// The profile's values for a width × height canvas (the profile checked
// their types when it was loaded; counts are clamped to what the passes hold).
RcSettings rc_settings(const Profile& profile, std::uint32_t width, std::uint32_t height);

}  // namespace gi
