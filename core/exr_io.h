// Multi-layer OpenEXR I/O for images (captures, references, reports).
// Layer "" is written as channels R, G, B; layer "di" as di.R, di.G, di.B.
// Float32 (or half, for stored baselines), ZIP compression, written to a temporary name and renamed, so a
// reader never sees a partial file (docs/design.md §11).
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"

namespace gi {

enum class ExrPixels { float32, half };

// Every layer must have the same (non-zero) size; layer names must be unique.
// Half rounds to 11 significant bits (relative error ≤ 2^-11) and clamps at
// 65504: enough to compare and look at, half the bytes of float32.
// Throws std::invalid_argument on bad arguments, std::runtime_error when the
// file cannot be written (nothing is left at `path` then).
void write_exr(const std::filesystem::path& path,
               const std::vector<std::pair<std::string, const Image*>>& layers,
               ExrPixels pixels = ExrPixels::float32);

// Reads every layer that has R, G or B channels (missing ones read as 0); a
// layer with a single other channel (e.g. "depth.Z", "Y") is read as grey.
// Half and uint channels are converted to float. Any error (missing file,
// not an EXR, truncated data) throws gi::InputError naming the file.
std::map<std::string, Image> read_exr(const std::filesystem::path& path);

}  // namespace gi
