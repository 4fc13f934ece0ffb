#include "core/cache_root.h"

#include <cstdlib>

namespace gi {

std::filesystem::path cache_root() {
  if (const char* dir = std::getenv("GIHARNESS_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "giharness";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "giharness";
  return std::filesystem::temp_directory_path() / "giharness-cache";
}

}  // namespace gi
