#include "core/texture_decode.h"

#include <climits>
#include <cstring>

#include <stb/stb_image.h>

namespace gi {

bool decode_texture_image(const unsigned char* bytes, std::size_t size, TextureImage& out, std::string& why) {
  if (size == 0 || size > std::size_t(INT_MAX)) {
    why = "an encoded image of 1 byte to 2 GiB";
    return false;
  }
  int w = 0, h = 0, channels = 0;
  // Size first: a header that claims a huge image is refused before stb
  // allocates for it.
  if (!stbi_info_from_memory(bytes, int(size), &w, &h, &channels)) {
    why = std::string("a PNG or JPEG image (stb_image: ") + stbi_failure_reason() + ")";
    return false;
  }
  if (w <= 0 || h <= 0 || std::uint32_t(w) > kMaxTextureSide || std::uint32_t(h) > kMaxTextureSide) {
    why = "an image of at most " + std::to_string(kMaxTextureSide) + " texels a side (got " + std::to_string(w) + "×" +
          std::to_string(h) + ")";
    return false;
  }
  stbi_uc* pixels = stbi_load_from_memory(bytes, int(size), &w, &h, &channels, 4);
  if (!pixels) {
    why = std::string("a PNG or JPEG image (stb_image: ") + stbi_failure_reason() + ")";
    return false;
  }
  out.width = std::uint32_t(w);
  out.height = std::uint32_t(h);
  out.rgba.assign(pixels, pixels + std::size_t(w) * std::size_t(h) * 4);
  stbi_image_free(pixels);
  return true;
}

}  // namespace gi
