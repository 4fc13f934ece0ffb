#include "checks/check_result.h"

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
  return j;
}

}  // namespace gi
