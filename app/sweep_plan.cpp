#include "app/sweep_plan.h"

#include <algorithm>
#include <regex>

#include "core/errors.h"
#include "core/scenario.h"

namespace gi {
namespace {

nlohmann::json parse_value(const std::string& key, const std::string& text) {
  static const std::regex wxh(R"((\d+)x(\d+))");
  std::smatch m;
  if (key == "resolution" && std::regex_match(text, m, wxh))
    return nlohmann::json::array({std::stoul(m[1].str()), std::stoul(m[2].str())});
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    return text;
  }
}

void apply(nlohmann::json& doc, const std::string& key, const std::string& text) {
  const nlohmann::json value = parse_value(key, text);
  const auto& top = scenario_keys().top_level;
  if (!key.empty() && key[0] == '/') {
    const nlohmann::json::json_pointer ptr(key);
    if (!doc.contains(ptr.parent_pointer()))
      throw InputError("--vary", key, "a JSON Pointer whose parent exists in the scenario");
    doc[ptr] = value;
  } else if (std::find(top.begin(), top.end(), key) != top.end()) {
    doc[key] = value;
  } else {
    if (!doc.contains("overrides")) doc["overrides"] = nlohmann::json::object();
    doc["overrides"][key] = value;
  }
}

}  // namespace

std::string SweepPoint::label() const {
  std::string out;
  for (const auto& [k, v] : settings) out += (out.empty() ? "" : " ") + k + "=" + v;
  return out;
}

std::string SweepPoint::slug() const {
  std::string out;
  for (const auto& [k, v] : settings) {
    if (!out.empty()) out += '_';
    for (char ch : k + "-" + v) out += std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '.' ? ch : '_';
  }
  return out.empty() ? "base" : out;
}

SweepAxis parse_sweep_axis(const std::string& item) {
  const std::size_t eq = item.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 >= item.size())
    throw InputError("--vary", "", "expected key=v1,v2,..., got \"" + item + "\"");
  SweepAxis axis;
  axis.key = item.substr(0, eq);
  std::string rest = item.substr(eq + 1);
  // Commas inside brackets belong to one value ([64,36]).
  int depth = 0;
  std::string current;
  for (char ch : rest) {
    if (ch == '[' || ch == '{') ++depth;
    if (ch == ']' || ch == '}') --depth;
    if (ch == ',' && depth == 0) {
      axis.values.push_back(current);
      current.clear();
    } else {
      current += ch;
    }
  }
  axis.values.push_back(current);
  for (const std::string& v : axis.values)
    if (v.empty()) throw InputError("--vary", axis.key, "no empty values in \"" + item + "\"");
  return axis;
}

std::vector<SweepPoint> sweep_points(const nlohmann::json& base, const std::vector<SweepAxis>& axes) {
  std::vector<SweepPoint> points = {SweepPoint{{}, base}};
  for (const SweepAxis& axis : axes) {
    std::vector<SweepPoint> next;
    for (const SweepPoint& p : points)
      for (const std::string& v : axis.values) {
        SweepPoint q = p;
        q.settings.emplace_back(axis.key, v);
        apply(q.document, axis.key, v);
        next.push_back(std::move(q));
      }
    points = std::move(next);
  }
  return points;
}

}  // namespace gi
