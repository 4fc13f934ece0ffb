// Figures in JSON: finite numbers stay numbers; NaN and ±inf become the
// strings "nan", "inf", "-inf" (JSON has no such numbers, and a silent null
// would hide exactly the values a user needs to see).
#pragma once
#include <cmath>

#include <nlohmann/json.hpp>

namespace gi {

inline nlohmann::json json_figure(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

}  // namespace gi
