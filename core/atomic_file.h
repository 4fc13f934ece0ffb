// Every file the harness writes goes through here: written to a temporary
// name in the same directory, flushed, then renamed over the target, so a
// reader (or a crash) never sees a half-written result.
#pragma once
#include <filesystem>
#include <functional>
#include <string_view>

#include <nlohmann/json.hpp>

namespace gi {

// Calls write(tmp_path) to produce the file, then renames tmp_path → path.
// On failure the temporary file is removed and the exception propagates.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

void write_text_file(const std::filesystem::path& path, std::string_view text);
void write_json_file(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace gi
