#include "core/data_dir.h"

#include <cstdlib>

#include <fmt/format.h>

namespace gi {

namespace fs = std::filesystem;

namespace {

// Absolute and without a trailing separator: shader names and cache keys are
// taken relative to it.
fs::path clean(const fs::path& p) {
  fs::path a = fs::absolute(p).lexically_normal();
  return a.has_filename() || !a.has_relative_path() ? a : a.parent_path();
}

bool is_data_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir / "gpu" / "shaders", ec) && fs::is_directory(dir / "scenarios" / "profiles", ec);
}

const char* const kHint =
    "set GIHARNESS_DATA_DIR to a folder holding gpu/shaders and scenarios/profiles (an installed "
    "<prefix>/share/giharness or a source checkout), or install with `cmake --install`";

}  // namespace

fs::path find_data_dir(const char* env, const fs::path& exe) {
  if (env && *env) {
    if (is_data_dir(env)) return clean(env);
    throw DataDirError(fmt::format("no giharness data folder at GIHARNESS_DATA_DIR={} (no gpu/shaders and "
                                   "scenarios/profiles there); {}",
                                   env, kHint));
  }
  // Lexical "..": /proc/self/exe has no symlinks left, so it is the physical parent.
  const fs::path exe_dir = exe.parent_path();
  const fs::path candidates[] = {(exe_dir / ".." / "share" / "giharness").lexically_normal(),
                                 exe_dir / "share" / "giharness"};
  std::string tried;
  for (const fs::path& c : candidates) {
    if (is_data_dir(c)) return clean(c);
    tried += (tried.empty() ? "" : ", ") + c.string();
  }
  throw DataDirError(
      fmt::format("giharness data folder not found (GIHARNESS_DATA_DIR unset; tried {}); {}", tried, kHint));
}

const fs::path& data_dir() {
  // A throw leaves the static unset, so a later call tries again.
  static const fs::path dir = [] {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw DataDirError("giharness data folder not found: cannot read /proc/self/exe; set GIHARNESS_DATA_DIR");
    return find_data_dir(std::getenv("GIHARNESS_DATA_DIR"), exe);
  }();
  return dir;
}

}  // namespace gi
