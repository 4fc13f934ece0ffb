// Texture image decoding for the glTF importer: PNG and JPEG bytes to RGBA8
// through stb_image (Debian's libstb), one place for the limits.
#pragma once
#include <cstddef>
#include <string>

#include "core/scene.h"

namespace gi {

// Larger images are refused on import: 16384² RGBA8 is 1 GiB already, and the
// device's storage-buffer range bounds the sum (replay/resource_limits.h).
inline constexpr std::uint32_t kMaxTextureSide = 16384;

// Fills out.width/height/rgba. False, with stb's reason or the limit, when the
// bytes are not an image stb decodes or the image is larger than allowed.
bool decode_texture_image(const unsigned char* bytes, std::size_t size, TextureImage& out, std::string& why);

}  // namespace gi
