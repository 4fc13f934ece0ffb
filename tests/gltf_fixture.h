// A valid one-triangle glTF document that tests break in one place at a
// time (tests/gltf_import_test.cpp, tests/bad_input_test.cpp).
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi::test {

using nlohmann::json;

inline std::string base64(const std::vector<unsigned char>& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = unsigned(in[i]) << 16 | unsigned(in[i + 1]) << 8 | in[i + 2];
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = unsigned(in[i]) << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = unsigned(in[i]) << 16 | unsigned(in[i + 1]) << 8;
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

template <class T>
inline void append(std::vector<unsigned char>& b, const std::vector<T>& v) {
  const std::size_t at = b.size();
  b.resize(at + v.size() * sizeof(T));
  std::memcpy(b.data() + at, v.data(), v.size() * sizeof(T));
}

// A valid one-triangle glTF: positions (36 bytes) then three u16 indices.
struct TinyGltf {
  std::vector<float> positions{0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::vector<std::uint16_t> indices{0, 1, 2};

  std::vector<unsigned char> bytes() const {
    std::vector<unsigned char> b;
    append(b, positions);
    append(b, indices);
    b.resize((b.size() + 3) & ~std::size_t(3), 0);
    return b;
  }

  json doc() const {
    const auto b = bytes();
    return json{
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", json::array({{{"nodes", {0}}}})},
        {"nodes", json::array({{{"name", "tri"}, {"mesh", 0}}})},
        {"meshes", json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}})}}})},
        {"buffers", json::array({{{"byteLength", b.size()},
                                  {"uri", "data:application/octet-stream;base64," + base64(b)}}})},
        {"bufferViews", json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
                                     {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}})},
        {"accessors", json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                                   {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}})},
    };
  }
};

}  // namespace gi::test
