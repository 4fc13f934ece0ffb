#include "core/rc/rc_settings.h"

#include <algorithm>
#include <cmath>


namespace gi {

std::uint32_t rc_cascades_for_diagonal(float diagonal, float interval0, std::uint32_t max_cascades) {
  const double a = std::max(double(interval0), 1.0);
  const double n = std::ceil(std::log(1.0 + 3.0 * double(diagonal) / a) / std::log(4.0));
  return std::clamp(std::uint32_t(std::max(n, 1.0)), 1u, std::max(max_cascades, 1u));
}

std::vector<float> RcSettings::interval_boundaries() const {
  std::vector<float> out;
  for (std::uint32_t c = 1; c < cascades; ++c) out.push_back(probe(c).start);
  return out;
}

nlohmann::json RcSettings::to_json() const {
  nlohmann::json probes = nlohmann::json::array();
  for (std::uint32_t c = 0; c < cascades; ++c) {
    const shader::RcProbe p = probe(c);
    probes.push_back({{"cascade", c}, {"width", p.width}, {"rays", p.width * p.width}, {"start", p.start},
                      {"range", p.range}});
  }
  return {{"canvas", {width, height}},
          {"distance_field", jfa ? "jfa" : "analytic"},
          {"resolution_factor", resolution_factor},
          {"interval0", interval0},
          {"cascades_for_diagonal", cascades_for_diagonal},
          {"cascades", cascades},
          {"probes", probes},
          {"mipmap", {mip_width(), mip_height()}},
          {"mipmap_divisor", mipmap_mode == shader::RC_MIPMAP_RAY_COUNT ? "ray_count" : "probe_width_x2"},
          {"merge", merge == shader::RC_MERGE_BILINEAR_FIX ? "bilinear_fix" : "lesson"}};
}

RcSettings rc_settings_for_canvas(RcSettings s, std::uint32_t width, std::uint32_t height) {
  s.width = width;
  s.height = height;
  s.cascades_for_diagonal =
      s.cascade_count > 0 ? std::min(s.cascade_count, s.max_cascades)
                          : rc_cascades_for_diagonal(std::sqrt(float(width) * float(width) + float(height) * float(height)),
                                                     s.interval0, s.max_cascades);
  s.cascades = s.cascades_for_diagonal;
  // The widest probe must tile the canvas (the lesson's code tightens the count so).
  while (s.cascades > 1 && (width % s.probe(s.cascades - 1).width != 0 || height % s.probe(s.cascades - 1).width != 0))
    --s.cascades;
  return s;
}

}  // namespace gi
