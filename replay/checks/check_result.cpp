#include "replay/checks/check_result.h"

namespace gi {

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::pass: return "pass";
    case Verdict::fail: return "fail";
    case Verdict::inconclusive: return "inconclusive";
  }
  return "fail";
}

nlohmann::json CheckResult::to_json() const {
  nlohmann::json j;
  j["name"] = name;
  j["verdict"] = to_string(verdict);
  j["message"] = message;
  j["figures"] = figures;
  j["limits"] = limits;
  j["first_failing_frame"] = first_failing_frame ? nlohmann::json(*first_failing_frame) : nlohmann::json(nullptr);
  j["evidence"] = evidence;
  return j;
}

}  // namespace gi
