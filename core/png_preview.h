// PNG previews of HDR images for people (reports, quick looks): exposure,
// clamp, sRGB encode. Never used for measurements — those read the EXR.
#pragma once
#include <filesystem>

#include "core/image.h"

namespace gi {

void write_png_preview(const std::filesystem::path& path, const Image& image, float exposure = 1.0f);

}  // namespace gi
