#include "core/atomic_file.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

namespace gi {

void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path& tmp)>& write) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  try {
    write(tmp);
    // fsync so the rename never exposes an empty file after a power loss.
    int fd = ::open(tmp.c_str(), O_RDONLY);
    if (fd >= 0) {
      ::fsync(fd);
      ::close(fd);
    }
    std::filesystem::rename(tmp, path);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

void write_text_file(const std::filesystem::path& path, std::string_view text) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write " + tmp.string());
  });
}

void write_json_file(const std::filesystem::path& path, const nlohmann::json& json) {
  // nlohmann writes NaN/inf as null; figures that may be non-finite go
  // through reports/json_figures.h (json_figure) first, which spells them out.
  write_text_file(path, json.dump(2) + "\n");
}

}  // namespace gi
