#include "core/exr_io.h"

#include <atomic>
#include <set>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <Imath/half.h>

#include "core/errors.h"

namespace gi {
namespace {

constexpr const char* kComponents[3] = {"R", "G", "B"};

std::string channel_name(const std::string& layer, const char* c) {
  return layer.empty() ? std::string(c) : layer + "." + c;
}

// A unique sibling name for write-then-rename (same directory: rename is atomic).
std::filesystem::path temp_sibling(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path t = path;
  t += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter.fetch_add(1));
  return t;
}

}  // namespace

void write_exr(const std::filesystem::path& path, const std::vector<std::pair<std::string, const Image*>>& layers,
               ExrPixels pixels) {
  if (layers.empty()) throw std::invalid_argument("write_exr: no layers for " + path.string());
  const std::uint32_t w = layers.front().second->width, h = layers.front().second->height;
  if (w == 0 || h == 0) throw std::invalid_argument("write_exr: empty image for " + path.string());
  std::set<std::string> names;
  for (const auto& [name, image] : layers) {
    if (image == nullptr || image->width != w || image->height != h || image->size() != std::size_t(w) * h)
      throw std::invalid_argument("write_exr: layer '" + name + "' has a different size in " + path.string());
    if (!names.insert(name).second)
      throw std::invalid_argument("write_exr: layer '" + name + "' given twice for " + path.string());
  }

  Imf::Header header(static_cast<int>(w), static_cast<int>(h));
  header.compression() = Imf::ZIP_COMPRESSION;
  Imf::FrameBuffer fb;
  const bool half = pixels == ExrPixels::half;
  const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
  const std::size_t component = half ? sizeof(Imath::half) : sizeof(float);
  const std::size_t xs = 3 * component, ys = 3 * component * w;
  std::vector<std::vector<Imath::half>> halves;  // the half copies the slices point into
  for (const auto& [name, image] : layers) {
    // OpenEXR's Slice takes a non-const pointer; writing only reads through it.
    char* base = const_cast<char*>(reinterpret_cast<const char*>(image->pixels.data()));
    if (half) {
      std::vector<Imath::half>& copy = halves.emplace_back(image->size() * 3);
      for (std::size_t i = 0; i < image->size(); ++i)
        for (int c = 0; c < 3; ++c) copy[3 * i + c] = Imath::half(image->pixels[i][c]);
      base = reinterpret_cast<char*>(copy.data());
    }
    for (int c = 0; c < 3; ++c) {
      const std::string ch = channel_name(name, kComponents[c]);
      header.channels().insert(ch, Imf::Channel(type));
      fb.insert(ch, Imf::Slice(type, base + c * component, xs, ys));
    }
  }

  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  const std::filesystem::path tmp = temp_sibling(path);
  try {
    {
      Imf::OutputFile file(tmp.c_str(), header);
      file.setFrameBuffer(fb);
      file.writePixels(static_cast<int>(h));
    }
    std::filesystem::rename(tmp, path);
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("write_exr: cannot write " + path.string() + ": " + e.what());
  }
}

std::map<std::string, Image> read_exr(const std::filesystem::path& path) {
  std::map<std::string, Image> out;
  try {
    if (!std::filesystem::is_regular_file(path)) throw std::runtime_error("no such file");
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const long long w = static_cast<long long>(dw.max.x) - dw.min.x + 1;
    const long long h = static_cast<long long>(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > (1ll << 31)) throw std::runtime_error("bad data window");

    // Group channels by layer (everything before the last '.').
    std::map<std::string, std::vector<std::string>> by_layer;  // layer -> channel suffixes
    const Imf::ChannelList& channels = file.header().channels();
    for (auto it = channels.begin(); it != channels.end(); ++it) {
      const std::string full = it.name();
      const std::size_t dot = full.rfind('.');
      const std::string layer = dot == std::string::npos ? std::string() : full.substr(0, dot);
      by_layer[layer].push_back(dot == std::string::npos ? full : full.substr(dot + 1));
    }

    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(glm::vec3), ys = sizeof(glm::vec3) * static_cast<std::size_t>(w);
    for (const auto& [layer, suffixes] : by_layer) {
      bool rgb = false;
      for (const std::string& s : suffixes) rgb |= (s == "R" || s == "G" || s == "B");
      if (!rgb && suffixes.size() != 1) continue;  // not an image layer we understand
      Image& img = out[layer];
      img = Image(static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h));
      // Slices are addressed from the data window's origin.
      char* base = reinterpret_cast<char*>(img.pixels.data()) - (static_cast<std::ptrdiff_t>(dw.min.x) * xs +
                                                                  static_cast<std::ptrdiff_t>(dw.min.y) * ys);
      if (rgb) {
        for (int c = 0; c < 3; ++c) {
          // Absent channels are filled with 0 (the fill value).
          fb.insert(channel_name(layer, kComponents[c]),
                    Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys, 1, 1, 0.0));
        }
      } else {
        // One grey channel: read it into R, then copy to G and B below.
        fb.insert(channel_name(layer, suffixes.front().c_str()), Imf::Slice(Imf::FLOAT, base, xs, ys, 1, 1, 0.0));
      }
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    for (auto& [layer, img] : out) {
      bool rgb = false;
      for (const std::string& s : by_layer[layer]) rgb |= (s == "R" || s == "G" || s == "B");
      if (!rgb)
        for (glm::vec3& p : img.pixels) p.y = p.z = p.x;
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path.string(), "", std::string("a readable OpenEXR image (") + e.what() + ")");
  }
  return out;
}

}  // namespace gi
