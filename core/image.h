// A linear HDR RGB image, row-major from the top-left pixel, float32.
#pragma once
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace gi {

struct Image {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::vector<glm::vec3> pixels;

  Image() = default;
  Image(std::uint32_t w, std::uint32_t h) : width(w), height(h), pixels(std::size_t(w) * h, glm::vec3(0.0f)) {}
  glm::vec3& at(std::uint32_t x, std::uint32_t y) { return pixels[std::size_t(y) * width + x]; }
  const glm::vec3& at(std::uint32_t x, std::uint32_t y) const { return pixels[std::size_t(y) * width + x]; }
  std::size_t size() const { return pixels.size(); }
};

// a + b and a − b, pixel by pixel (same size).
inline Image sum_images(const Image& a, const Image& b) {
  Image s = a;
  for (std::size_t i = 0; i < s.pixels.size(); ++i) s.pixels[i] += b.pixels[i];
  return s;
}
inline Image difference_images(const Image& a, const Image& b) {
  Image d = a;
  for (std::size_t i = 0; i < d.pixels.size(); ++i) d.pixels[i] -= b.pixels[i];
  return d;
}

}  // namespace gi
