// Errors that map to the CLI's exit codes (docs/design.md §11).
#pragma once
#include <stdexcept>
#include <string>

namespace gi {

// Bad input: exit code 2. The message names the file, the JSON path (or the
// glTF path such as /meshes/0/primitives/1) and what was expected.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::string json_path, std::string expected)
      : std::runtime_error(file + ": " + (json_path.empty() ? std::string("/") : json_path) + ": " + expected),
        file_(std::move(file)), json_path_(std::move(json_path)), expected_(std::move(expected)) {}
  const std::string& file() const { return file_; }
  const std::string& json_path() const { return json_path_; }
  const std::string& expected() const { return expected_; }

 private:
  std::string file_, json_path_, expected_;
};

// No usable device, a Vulkan failure, or an internal error: exit code 3.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// giharness's data folder (shaders, profiles; core/data_dir.h) not found:
// exit code 3, since the installation is broken, not the user's input. The
// message names every place tried.
class DataDirError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace gi
