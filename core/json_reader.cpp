#include "core/json_reader.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/scenario.h"  // json_pointer_token

namespace gi {

using json = nlohmann::json;

namespace {

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

}  // namespace

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + v[i];
  return out;
}

std::string got(const json& j) {
  std::string d = j.dump();
  if (d.size() > 60) d = d.substr(0, 57) + "...";
  const char* t = j.is_string() ? "string" : j.is_boolean() ? "boolean" : j.is_number() ? "number"
                  : j.is_array() ? "array" : j.is_object() ? "object" : "null";
  return fmt::format("got {} {}", t, d);
}

void JsonReader::fail(const std::string& path, const std::string& expected) const {
  throw InputError(file_, path, expected);
}

std::string JsonReader::at(const std::string& path, const std::string& key) {
  return path + "/" + json_pointer_token(key);
}

void JsonReader::object(const json& j, const std::string& path, const std::vector<std::string>& allowed,
                        const std::vector<std::string>& required) const {
  if (!j.is_object()) fail(path, "expected an object, " + got(j));
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!contains(allowed, it.key()))
      fail(at(path, it.key()), fmt::format("unknown key \"{}\"; expected one of: {}", it.key(), join(allowed)));
  for (const std::string& r : required)
    if (!j.contains(r)) fail(at(path, r), fmt::format("missing required key \"{}\"", r));
}

std::string JsonReader::string(const json& j, const std::string& path, bool non_empty) const {
  if (!j.is_string()) fail(path, "expected a string, " + got(j));
  std::string s = j.get<std::string>();
  if (non_empty && s.empty()) fail(path, "expected a non-empty string");
  return s;
}

std::string JsonReader::one_of(const json& j, const std::string& path, const std::vector<std::string>& options) const {
  if (!j.is_string()) fail(path, fmt::format("expected one of {}, {}", join(options), got(j)));
  std::string s = j.get<std::string>();
  if (!contains(options, s)) fail(path, fmt::format("expected one of {}, got \"{}\"", join(options), s));
  return s;
}

bool JsonReader::boolean(const json& j, const std::string& path) const {
  if (!j.is_boolean()) fail(path, "expected true or false, " + got(j));
  return j.get<bool>();
}

std::uint32_t JsonReader::uint(const json& j, const std::string& path, std::uint64_t lo, std::uint64_t hi) const {
  const std::string range = fmt::format("an integer in {}..{}", lo, hi);
  if (j.is_number_unsigned() || (j.is_number_integer() && j.get<std::int64_t>() >= 0)) {
    std::uint64_t v = j.get<std::uint64_t>();
    if (v < lo || v > hi) fail(path, fmt::format("expected {}, got {}", range, v));
    return static_cast<std::uint32_t>(v);
  }
  if (j.is_number_integer()) fail(path, fmt::format("expected {}, got {}", range, j.get<std::int64_t>()));
  fail(path, fmt::format("expected {}, {}", range, got(j)));
}

float JsonReader::number(const json& j, const std::string& path, double lo, double hi) const {
  if (!j.is_number()) fail(path, fmt::format("expected a number in [{}, {}], {}", lo, hi, got(j)));
  double v = j.get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) fail(path, fmt::format("expected a number in [{}, {}], got {}", lo, hi, v));
  return static_cast<float>(v);
}

glm::vec3 JsonReader::vec3(const json& j, const std::string& path, double lo, double hi) const {
  if (!j.is_array() || j.size() != 3)
    fail(path, fmt::format("expected an array of 3 numbers in [{}, {}], {}", lo, hi, got(j)));
  return glm::vec3(number(j[0], at(path, 0), lo, hi), number(j[1], at(path, 1), lo, hi),
                   number(j[2], at(path, 2), lo, hi));
}

const json& JsonReader::array(const json& j, const std::string& path, std::size_t min_items) const {
  if (!j.is_array()) fail(path, "expected an array, " + got(j));
  if (j.size() < min_items) fail(path, fmt::format("expected an array of at least {} item(s)", min_items));
  return j;
}

}  // namespace gi
