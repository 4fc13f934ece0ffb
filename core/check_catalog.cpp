#include "core/check_catalog.h"

#include "core/scenario.h"

#include <algorithm>
#include <stdexcept>

namespace gi {
namespace {

// A function-local static: declarations arrive during static initialisation,
// in an order the linker chooses.
std::vector<CheckDeclaration>& catalog() {
  static std::vector<CheckDeclaration> declarations;
  return declarations;
}

// The model in words, as the schema's description ends.
std::string model_text(const CheckModel& m) {
  return "Statistical model (" + std::string(to_string(m.basis)) + "): estimates " + m.estimates + ". Noise: " + m.noise +
         ". False-alarm rate: " + m.false_alarm + ".";
}

}  // namespace

const char* to_string(CheckModel::Basis basis) {
  switch (basis) {
    case CheckModel::Basis::exact: return "exact";
    case CheckModel::Basis::derived: return "derived";
    case CheckModel::Basis::measured: return "measured";
  }
  return "measured";
}

void declare_check(CheckDeclaration declaration) {
  std::vector<CheckDeclaration>& c = catalog();
  if (find_declared_check(declaration.name)) throw std::logic_error("check declared twice: " + declaration.name);
  const nlohmann::json schema = nlohmann::json::parse(declaration.schema, nullptr, /*allow_exceptions=*/false);
  if (!schema.is_object() || !schema.contains("properties") || !schema["properties"].is_object() ||
      !schema["properties"].contains("name"))
    throw std::logic_error("check " + declaration.name + ": its schema is not an object schema with a \"name\" property");
  const CheckModel& m = declaration.model;
  if (m.estimates.empty() || m.noise.empty() || m.false_alarm.empty() || !(m.false_alarm_rate >= 0.0 && m.false_alarm_rate < 1.0) ||
      (m.basis == CheckModel::Basis::exact) != (m.false_alarm_rate == 0.0))
    throw std::logic_error("check " + declaration.name + ": its statistical model is not stated (CheckModel)");
  declaration.keys.clear();
  for (const auto& [key, value] : schema["properties"].items()) declaration.keys.push_back(key);
  const auto at = std::lower_bound(c.begin(), c.end(), declaration.name,
                                   [](const CheckDeclaration& d, const std::string& n) { return d.name < n; });
  c.insert(at, std::move(declaration));
}

const std::vector<CheckDeclaration>& declared_checks() { return catalog(); }

const CheckDeclaration* find_declared_check(const std::string& name) {
  for (const CheckDeclaration& d : catalog())
    if (d.name == name) return &d;
  return nullptr;
}

nlohmann::ordered_json with_declared_checks(nlohmann::ordered_json schema) {
  nlohmann::ordered_json& defs = schema["$defs"];
  nlohmann::ordered_json kept = nlohmann::ordered_json::object();
  for (auto& [key, value] : defs.items())
    if (key.rfind("check_", 0) != 0) kept[key] = value;
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  nlohmann::ordered_json by_name = nlohmann::ordered_json::array();
  for (const CheckDeclaration& d : declared_checks()) {
    names.push_back(d.name);
    nlohmann::ordered_json rule;
    rule["if"]["properties"]["name"]["const"] = d.name;
    rule["then"]["$ref"] = "#/$defs/check_" + d.name;
    by_name.push_back(rule);
  }
  nlohmann::ordered_json& check = kept["check"];
  check["properties"]["name"]["enum"] = names;
  check["allOf"] = by_name;
  for (const CheckDeclaration& d : declared_checks()) {
    nlohmann::ordered_json c = nlohmann::ordered_json::parse(d.schema);
    const std::string own = c.value("description", "");
    c["description"] = own.empty() ? model_text(d.model) : own + " " + model_text(d.model);
    kept["check_" + d.name] = std::move(c);
  }
  defs = kept;
  return schema;
}

void drop_rerunning_checks(Scenario& scenario) {
  std::erase_if(scenario.checks, [](const CheckSpec& c) {
    const CheckDeclaration* d = find_declared_check(c.name);
    return d && d->reruns_scenario;
  });
}

}  // namespace gi
