#include "core/profile.h"

#include <cstdlib>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "core/data_dir.h"
#include "core/errors.h"
#include "core/json_input.h"
#include "core/scenario.h"

namespace gi {

using nlohmann::json;

namespace {

const char* type_name(const json& v) {
  if (v.is_boolean()) return "a boolean";
  if (v.is_number_integer()) return "an integer";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  return "an unsupported type";
}

bool supported(const json& v) { return v.is_boolean() || v.is_number() || v.is_string(); }

// Can `v` replace `base`? Integers stay integers; numbers accept integers.
bool same_type(const json& base, const json& v) {
  if (base.is_boolean()) return v.is_boolean();
  if (base.is_number_integer()) return v.is_number_integer();
  if (base.is_number()) return v.is_number();
  if (base.is_string()) return v.is_string();
  return false;
}

std::string list(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

void set_value(Profile& p, const std::string& key, const json& v, const std::string& file, const std::string& path,
               const std::string& set_by) {
  auto it = p.values.find(key);
  if (it == p.values.end()) {
    std::vector<std::string> keys;
    for (const auto& [k, _] : p.values) keys.push_back(k);
    throw InputError(file, path, fmt::format("a key of profile {} ({}), got \"{}\"", p.name, list(keys), key));
  }
  ProfileValue& pv = it->second;
  if (!same_type(pv.value, v))
    throw InputError(file, path, fmt::format("{} for {} (the profile's value is {}), got {}", type_name(pv.value), key,
                                             pv.value.dump(), v.dump()));
  if (!pv.allowed.empty() && std::find(pv.allowed.begin(), pv.allowed.end(), v.get<std::string>()) == pv.allowed.end())
    throw InputError(file, path, fmt::format("one of {} for {}, got {}", list(pv.allowed), key, v.dump()));
  pv.value = v;
  pv.set_by = set_by;
}

}  // namespace

long long Profile::integer(const std::string& key) const {
  auto it = values.find(key);
  if (it == values.end() || !it->second.value.is_number_integer())
    throw std::logic_error("profile " + name + ": no integer " + key);
  return it->second.value.get<long long>();
}

double Profile::number(const std::string& key) const {
  auto it = values.find(key);
  if (it == values.end() || !it->second.value.is_number()) throw std::logic_error("profile " + name + ": no number " + key);
  return it->second.value.get<double>();
}

bool Profile::flag(const std::string& key) const {
  auto it = values.find(key);
  if (it == values.end() || !it->second.value.is_boolean())
    throw std::logic_error("profile " + name + ": no boolean " + key);
  return it->second.value.get<bool>();
}

const std::string& Profile::text(const std::string& key) const {
  auto it = values.find(key);
  if (it == values.end() || !it->second.value.is_string()) throw std::logic_error("profile " + name + ": no string " + key);
  return it->second.value.get_ref<const std::string&>();
}

json Profile::to_json() const {
  json v = json::object();
  for (const auto& [k, pv] : values) v[k] = {{"value", pv.value}, {"source", pv.source}, {"set_by", pv.set_by}};
  return {{"name", name}, {"file", file.string()}, {"values", v}};
}

std::filesystem::path profile_dir() {
  if (const char* d = std::getenv("GIHARNESS_PROFILE_DIR"); d && *d) return d;
  return data_dir() / "scenarios" / "profiles";
}

Profile load_profile(const std::string& name_or_file, const std::filesystem::path& dir) {
  std::filesystem::path file = name_or_file;
  if (file.extension() != ".json" || !std::filesystem::exists(file)) file = dir / (name_or_file + ".json");
  const std::string f = file.string();
  const json doc = read_json_input(file, "a readable profile file (profile \"" + name_or_file + "\")");
  if (!doc.is_object()) throw InputError(f, "", "an object with \"name\" and \"values\"");
  for (auto it = doc.begin(); it != doc.end(); ++it)
    if (it.key() != "name" && it.key() != "description" && it.key() != "bevy_ref" && it.key() != "values")
      throw InputError(f, "/" + json_pointer_token(it.key()), "one of the keys name, description, bevy_ref, values");
  if (doc.contains("bevy_ref") && !doc["bevy_ref"].is_string())
    throw InputError(f, "/bevy_ref", "a Bevy tag or commit as a string");
  if (!doc.contains("name") || !doc["name"].is_string()) throw InputError(f, "/name", "the profile's name as a string");
  if (!doc.contains("values") || !doc["values"].is_object()) throw InputError(f, "/values", "an object of values");
  Profile p;
  p.name = doc["name"].get<std::string>();
  p.bevy_ref = doc.value("bevy_ref", std::string());
  p.file = file;
  for (auto it = doc["values"].begin(); it != doc["values"].end(); ++it) {
    const std::string path = "/values/" + json_pointer_token(it.key());
    const json& e = it.value();
    if (!e.is_object() || !e.contains("value") || !e.contains("source") || !e["source"].is_string())
      throw InputError(f, path, "an object {\"value\": …, \"source\": \"…\"}");
    for (auto k = e.begin(); k != e.end(); ++k)
      if (k.key() != "value" && k.key() != "source" && k.key() != "allowed" && k.key() != "cited")
        throw InputError(f, path + "/" + json_pointer_token(k.key()), "one of the keys value, source, allowed, cited");
    ProfileValue pv;
    pv.value = e["value"];
    pv.source = e["source"].get<std::string>();
    if (!supported(pv.value)) throw InputError(f, path + "/value", "a boolean, number or string");
    if (e.contains("cited")) {
      if (!e["cited"].is_object()) throw InputError(f, path + "/cited", "an object {citation: fingerprint}");
      for (auto c = e["cited"].begin(); c != e["cited"].end(); ++c) {
        if (!c.value().is_string())
          throw InputError(f, path + "/cited/" + json_pointer_token(c.key()), "a fingerprint as a string");
        pv.cited[c.key()] = c.value().get<std::string>();
      }
    }
    if (e.contains("allowed")) {
      if (!pv.value.is_string() || !e["allowed"].is_array())
        throw InputError(f, path + "/allowed", "an array of strings, for a string value only");
      for (const json& a : e["allowed"]) {
        if (!a.is_string()) throw InputError(f, path + "/allowed", "an array of strings");
        pv.allowed.push_back(a.get<std::string>());
      }
      if (std::find(pv.allowed.begin(), pv.allowed.end(), pv.value.get<std::string>()) == pv.allowed.end())
        throw InputError(f, path + "/value", "one of the allowed values " + list(pv.allowed));
    }
    p.values[it.key()] = std::move(pv);
  }
  return p;
}

namespace {
void append_profile_json(std::string& out, const nlohmann::ordered_json& v, int depth) {
  const auto pad = [&](int d) { out.append(static_cast<std::size_t>(2 * d), ' '); };
  if (v.is_object() && !v.empty()) {
    out += "{\n";
    std::size_t k = 0;
    for (auto it = v.begin(); it != v.end(); ++it, ++k) {
      pad(depth + 1);
      out += nlohmann::ordered_json(it.key()).dump(-1, ' ', true) + ": ";
      append_profile_json(out, it.value(), depth + 1);
      out += k + 1 < v.size() ? ",\n" : "\n";
    }
    pad(depth);
    out += "}";
  } else if (v.is_array()) {
    out += "[";
    for (std::size_t k = 0; k < v.size(); ++k) out += (k ? ", " : "") + v[k].dump(-1, ' ', true);
    out += "]";
  } else {
    out += v.dump(-1, ' ', true);
  }
}
}  // namespace

std::string profile_file_text(const nlohmann::ordered_json& doc) {
  std::string out;
  append_profile_json(out, doc, 0);
  return out + "\n";
}

void apply_overrides(Profile& profile, const json& overrides, const std::string& file, const std::string& json_path,
                     const std::string& set_by) {
  if (!overrides.is_object()) throw InputError(file, json_path, "an object of profile keys");
  for (auto it = overrides.begin(); it != overrides.end(); ++it)
    set_value(profile, it.key(), it.value(), file, json_path + "/" + json_pointer_token(it.key()), set_by);
}

void apply_set(Profile& profile, const std::string& assignment) {
  const std::size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set", "", "key=value, got \"" + assignment + "\"");
  const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  json v = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (v.is_discarded() || !supported(v)) v = text;  // a bare word is a string
  set_value(profile, key, v, "--set", "/" + json_pointer_token(key), "--set");
}

Profile resolve_profile(const Scenario& scenario, const std::optional<std::string>& profile_override,
                        const std::vector<std::string>& sets) {
  Profile p = load_profile(profile_override.value_or(scenario.profile));
  apply_overrides(p, scenario.overrides, scenario.file.string(), "/overrides", "scenario overrides");
  for (const std::string& s : sets) apply_set(p, s);
  return p;
}

}  // namespace gi
