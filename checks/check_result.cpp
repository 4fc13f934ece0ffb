#include "checks/check_result.h"

#include <algorithm>

#include "core/check_catalog.h"

namespace gi {

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::pass: return "pass";
    case Verdict::fail: return "fail";
    case Verdict::inconclusive: return "inconclusive";
  }
  return "fail";
}

nlohmann::json CheckResult::stated_limits() const {
  nlohmann::json l = limits;
  if (const CheckDeclaration* d = find_declared_check(name); d && !l.contains("false_alarm_rate"))
    l["false_alarm_rate"] = std::string(to_string(d->model.basis)) + ": " + d->model.false_alarm;
  return l;
}

nlohmann::json CheckResult::to_json() const {
  nlohmann::json j;
  j["name"] = name;
  j["verdict"] = to_string(verdict);
  j["message"] = message;
  j["figures"] = figures;
  j["limits"] = stated_limits();
  j["first_failing_frame"] = first_failing_frame ? nlohmann::json(*first_failing_frame) : nlohmann::json(nullptr);
  j["evidence"] = evidence;
  if (!region.is_null()) j["region"] = region;
  if (!region_mask.is_null()) j["region_mask"] = region_mask;
  return j;
}

nlohmann::json mask_bounds(const std::vector<bool>& mask, std::uint32_t width) {
  if (width == 0) return nullptr;
  std::uint32_t x0 = width, y0 = ~0u, x1 = 0, y1 = 0;
  bool any = false;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const std::uint32_t x = std::uint32_t(i % width), y = std::uint32_t(i / width);
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    any = true;
  }
  return any ? nlohmann::json{x0, y0, x1, y1} : nlohmann::json(nullptr);
}

}  // namespace gi
