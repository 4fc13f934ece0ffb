// Reading JSON input while knowing where each value is: every failure is a
// gi::InputError naming the file, the JSON Pointer of the value and what was
// expected (exit code 2). The scenario parser, the profile and every check's
// parameters read through it, so a user sees one style of message.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace gi {

// "a, b, c"
std::string join(const std::vector<std::string>& v);
// A short rendering of a value for "got …": "got number 3".
std::string got(const nlohmann::json& j);

class JsonReader {
 public:
  explicit JsonReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& path, const std::string& expected) const;

  static std::string at(const std::string& path, const std::string& key);  // key escaped as a JSON Pointer token
  static std::string at(const std::string& path, std::size_t i) { return path + "/" + std::to_string(i); }

  // An object with only `allowed` keys and every `required` one.
  void object(const nlohmann::json& j, const std::string& path, const std::vector<std::string>& allowed,
              const std::vector<std::string>& required = {}) const;
  std::string string(const nlohmann::json& j, const std::string& path, bool non_empty = true) const;
  std::string one_of(const nlohmann::json& j, const std::string& path, const std::vector<std::string>& options) const;
  bool boolean(const nlohmann::json& j, const std::string& path) const;
  std::uint32_t uint(const nlohmann::json& j, const std::string& path, std::uint64_t lo, std::uint64_t hi) const;
  // Finite, in [lo, hi].
  float number(const nlohmann::json& j, const std::string& path, double lo, double hi) const;
  glm::vec3 vec3(const nlohmann::json& j, const std::string& path, double lo, double hi) const;
  const nlohmann::json& array(const nlohmann::json& j, const std::string& path, std::size_t min_items = 0) const;

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

}  // namespace gi
