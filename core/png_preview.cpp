#include "core/png_preview.h"

#include <cmath>
#include <algorithm>
#include <stdexcept>
#include <vector>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "core/atomic_file.h"

namespace gi {
namespace {

std::uint8_t encode_srgb(float linear) {
  if (!std::isfinite(linear)) return 255;  // NaN/inf show as white, never as black
  const float c = std::clamp(linear, 0.0f, 1.0f);
  const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return static_cast<std::uint8_t>(std::lround(s * 255.0f));
}

}  // namespace

void write_png_preview(const std::filesystem::path& path, const Image& image, float exposure) {
  std::vector<std::uint8_t> rgb(image.size() * 3);
  for (std::size_t i = 0; i < image.size(); ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = encode_srgb(image.pixels[i][c] * exposure);
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    if (!stbi_write_png(tmp.c_str(), static_cast<int>(image.width), static_cast<int>(image.height), 3, rgb.data(),
                        static_cast<int>(image.width * 3)))
      throw std::runtime_error("cannot write " + tmp.string());
  });
}

}  // namespace gi
