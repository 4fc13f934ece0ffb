// The field's oracle against the importer: Khronos glTF-Validator
// (npm gltf-validator 2.0.0-dev.3.10, installed by .ci/setup, run through
// tests/gltf_validate.mjs) on every glTF the project ships. A file it finds
// errors in must make gi::import_gltf throw gi::InputError; a file it finds
// none in must import, or fail with InputError only for one of the
// unsupported features listed below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/gltf_import.h"

namespace gi {
namespace {

namespace fs = std::filesystem;

const fs::path kSourceDir = GIHARNESS_SOURCE_DIR;
const fs::path kValidatorPackage = "/usr/local/lib/giharness-node/node_modules/gltf-validator/package.json";

// Valid glTF the importer refuses on purpose, and why. Keep it short: each
// entry is a feature the harness does not support, not a bug.
const std::map<std::string, std::string> kUnsupportedButValid = {
    {"hostile_deep_extras.gltf",
     "JSON nested deeper than the input reader's limit (core/json_input.h), a guard against stack exhaustion"},
};

struct ValidatorReport {
  int errors = 0;
  std::string summary;  // the script's JSON line, for messages
};

std::vector<fs::path> shipped_gltf_files() {
  std::vector<fs::path> files;
  for (const char* dir : {"scenarios/assets", "tests/data/gltf", "tests/fuzz/corpus/gltf"}) {
    if (!fs::is_directory(kSourceDir / dir)) continue;
    for (const auto& e : fs::recursive_directory_iterator(kSourceDir / dir)) {
      const auto ext = e.path().extension();
      if (e.is_regular_file() && (ext == ".gltf" || ext == ".glb")) files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string shell_quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs tests/gltf_validate.mjs once on all files; one report per file path.
std::map<std::string, ValidatorReport> run_validator(const std::vector<fs::path>& files, std::string& problem) {
  std::string command = "node " + shell_quoted((kSourceDir / "tests/gltf_validate.mjs").string());
  for (const fs::path& f : files) command += " " + shell_quoted(f.string());
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), &pclose);
  std::map<std::string, ValidatorReport> reports;
  if (!pipe) {
    problem = "could not start node";
    return reports;
  }
  std::string output;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe.get())) > 0;) output.append(buf, n);
  const int status = pclose(pipe.release());
  if (status != 0) problem = "tests/gltf_validate.mjs exited with status " + std::to_string(status);
  std::size_t at = 0;
  while (at < output.size()) {
    const std::size_t end = std::min(output.find('\n', at), output.size());
    const std::string line = output.substr(at, end - at);
    at = end + 1;
    if (line.empty()) continue;
    const auto j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object() || !j.contains("file") || !j.contains("errors")) {
      problem = "unexpected output line from tests/gltf_validate.mjs: " + line;
      continue;
    }
    reports[j["file"].get<std::string>()] = {j["errors"].get<int>(), line};
  }
  return reports;
}

// "" when the file imports; else the InputError's message. Any other
// exception escapes and fails the test.
std::string import_error(const fs::path& file) {
  try {
    (void)import_gltf(file);
    return "";
  } catch (const InputError& e) {
    return e.what();
  }
}

TEST(GltfValidator, ImporterAgreesWithKhronosValidatorOnEveryShippedGltf) {
  ASSERT_EQ(std::system("command -v node >/dev/null 2>&1"), 0)
      << "node is not on PATH: run .ci/setup as root (it installs nodejs and the glTF validator)";
  ASSERT_TRUE(fs::is_regular_file(kValidatorPackage))
      << "Khronos glTF-Validator is not installed (" << kValidatorPackage << "): run .ci/setup as root";

  const std::vector<fs::path> files = shipped_gltf_files();
  ASSERT_GE(files.size(), 10u) << "scenarios/assets, tests/data/gltf and tests/fuzz/corpus/gltf hold the samples";
  std::string problem;
  const auto reports = run_validator(files, problem);
  ASSERT_TRUE(problem.empty()) << problem;

  std::size_t with_errors = 0, clean = 0;
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const auto r = reports.find(f.string());
    ASSERT_NE(r, reports.end()) << "no validator report";
    const std::string error = import_error(f);
    const auto unsupported = kUnsupportedButValid.find(f.filename().string());
    if (r->second.errors > 0) {
      ++with_errors;
      EXPECT_NE(error, "") << "imported a file the validator rejects: " << r->second.summary;
      EXPECT_EQ(unsupported, kUnsupportedButValid.end()) << "listed as valid but unsupported: " << r->second.summary;
    } else {
      ++clean;
      if (unsupported == kUnsupportedButValid.end())
        EXPECT_EQ(error, "") << "the validator finds no error, and no unsupported feature is documented";
      else
        EXPECT_NE(error, "") << "listed as unsupported (" << unsupported->second << ") but imports: drop it from the list";
    }
  }
  EXPECT_GT(with_errors, 0u);
  EXPECT_GT(clean, 0u);
}

}  // namespace
}  // namespace gi
