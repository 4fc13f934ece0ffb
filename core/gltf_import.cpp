#include "core/gltf_import.h"

// Debian ships TinyGLTF 2.7 as a shared library (libtinygltf.so, built with
// nlohmann-json and stb_image), and gi_core already links it (`tinygltf` →
// -ltinygltf). So this file includes the header WITHOUT TINYGLTF_IMPLEMENTATION
// (a second copy of every symbol would only be shadowed by the library's) and
// without any configuration macro: the class layouts must match the library's
// build. Image decoding is switched off at run time (SetImageLoader below).
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/gltf_schema.h"
#include "core/json_input.h"
#include "core/shared/texture_sampling.h"
#include "core/tangents.h"
#include "core/texture_decode.h"

namespace gi {
namespace {

using Json = nlohmann::json;

std::string idx(const std::string& base, std::size_t i) { return base + "/" + std::to_string(i); }

bool finite_f32(double v) {
  return std::isfinite(v) && std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ';';
  return s;
}

std::uint32_t read_u32le(const std::vector<unsigned char>& b, std::size_t at) {
  return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
         std::uint32_t(b[at + 3]) << 24;
}

// TinyGLTF file-system callbacks that only see files under the glTF's folder:
// the stock ones also search the current directory, which would make a missing
// buffer file depend on where the harness runs.
struct FsContext {
  std::string base_dir;  // absolute, no trailing slash
};

bool fs_file_exists(const std::string& path, void* user) {
  const auto* ctx = static_cast<const FsContext*>(user);
  if (path.rfind(ctx->base_dir + "/", 0) != 0) return false;
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

std::string fs_expand(const std::string& path, void*) { return path; }

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  if (!fs_file_exists(path, user)) {
    if (err) *err += "not a readable file: " + path;
    return false;
  }
  return tinygltf::ReadWholeFile(out, err, path, nullptr);
}

bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is disabled";
  return false;
}

// Images are never used: accept them without decoding.
// TinyGLTF hands every image's encoded bytes (from a uri or a bufferView) to
// this callback. They are kept encoded: the importer decodes only the images a
// material uses, and names the image's JSON path when one is broken.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->width = image->height = -1;  // not decoded
  return true;
}

class Importer {
 public:
  explicit Importer(std::filesystem::path file) : file_(std::move(file)), fname_(file_.string()) {}

  Scene run() {
    load();
    scene_.name = file_.stem().string();
    check_extensions();
    walk_scene();
    if (scene_.triangle_count() == 0)
      fail(scene_path_, "a scene with at least one triangle (none of its nodes reaches a TRIANGLES primitive)");
    if (!camera_found_) warn("no perspective camera in the scene: the default camera is kept");
    if (model_.animations.size())
      warn(std::to_string(model_.animations.size()) + " animation(s) ignored: the scene is static");
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& path, const std::string& expected) const {
    throw InputError(fname_, path, expected);
  }
  void warn(const std::string& s) { scene_.warnings.push_back("glTF " + fname_ + ": " + s); }

  // ---- loading -----------------------------------------------------------

  void load() {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file_, ec)) fail("", "an existing glTF file (.gltf or .glb)");
    if (std::filesystem::file_size(file_, ec) > 0xffffffffu || ec) fail("", "a readable glTF file under 4 GiB");
    std::vector<unsigned char> bytes;
    {
      std::ifstream in(file_, std::ios::binary);
      if (!in) fail("", "a readable glTF file");
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    if (bytes.size() > 0xffffffffu) fail("", "a glTF file under 4 GiB");
    const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;

    // Our own look at the JSON first, so that references TinyGLTF checks with
    // path-less messages get a JSON pointer here.
    std::string json_text;
    if (glb) {
      if (bytes.size() < 20) fail("", "a GLB file with a 12-byte header and a JSON chunk");
      if (read_u32le(bytes, 4) != 2) fail("", "a GLB container of version 2");
      const std::uint32_t total = read_u32le(bytes, 8);
      const std::uint32_t len = read_u32le(bytes, 12);
      if (total > bytes.size() || total < 20) fail("", "a GLB header length within the file size");
      if (read_u32le(bytes, 16) != 0x4E4F534Au) fail("", "a GLB whose first chunk is JSON");
      if (len > total - 20) fail("", "a GLB JSON chunk within the file");
      json_text.assign(reinterpret_cast<const char*>(bytes.data()) + 20, len);
    } else {
      json_text.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    }
    const Json j = parse_json_input(json_text, fname_);
    if (!j.is_object()) fail("", "a JSON object at the top level");
    // The glTF 2.0 schema, before TinyGLTF (lenient) reads it: every violation
    // is exit 2 with its JSON path (core/gltf_schema.h).
    validate_gltf_document(j, fname_, glb);

    std::filesystem::path base = std::filesystem::absolute(file_, ec).parent_path().lexically_normal();
    fs_.base_dir = base.string();
    while (fs_.base_dir.size() > 1 && fs_.base_dir.back() == '/') fs_.base_dir.pop_back();
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(tinygltf::FsCallbacks{&fs_file_exists, &fs_expand, &fs_read, &fs_write, &fs_});
    loader.SetImageLoader(&keep_encoded_image, nullptr);
    std::string err, warnings;
    bool ok = false;
    if (glb)
      ok = loader.LoadBinaryFromMemory(&model_, &err, &warnings, bytes.data(), static_cast<unsigned>(bytes.size()),
                                       fs_.base_dir);
    else
      ok = loader.LoadASCIIFromString(&model_, &err, &warnings, json_text.data(),
                                      static_cast<unsigned>(json_text.size()), fs_.base_dir);
    if (!ok || !err.empty()) fail("", "a valid glTF 2.0 file (TinyGLTF: " + trim(err.empty() ? "load failed" : err) + ")");
    if (!warnings.empty()) warn("loader: " + trim(warnings));
  }

  void check_extensions() {
    static const std::set<std::string> supported = {"KHR_lights_punctual", "KHR_materials_emissive_strength",
                                                    "KHR_materials_specular", "KHR_materials_ior",
                                                    "KHR_texture_transform"};
    for (std::size_t i = 0; i < model_.extensionsRequired.size(); ++i) {
      const std::string& e = model_.extensionsRequired[i];
      if (supported.count(e)) continue;
      // Compressed image formats (KHR_texture_basisu, EXT_texture_webp, ...)
      // are refused too: their textures would render as something else.
      fail(idx("/extensionsRequired", i), "only extensions this importer supports (KHR_lights_punctual, "
                                           "KHR_materials_emissive_strength, KHR_materials_specular, "
                                           "KHR_materials_ior, KHR_texture_transform); \"" + e + "\" is required");
    }
    for (const std::string& e : model_.extensionsUsed)
      if (!supported.count(e)) warn("extension " + e + " (used, not required) is ignored");
  }

  // ---- accessors ---------------------------------------------------------

  struct View {
    const unsigned char* data = nullptr;
    std::size_t stride = 0, count = 0;
    int component_type = 0;
  };

  static const char* type_name(int t) {
    switch (t) {
      case TINYGLTF_TYPE_SCALAR: return "SCALAR";
      case TINYGLTF_TYPE_VEC2: return "VEC2";
      case TINYGLTF_TYPE_VEC3: return "VEC3";
      case TINYGLTF_TYPE_VEC4: return "VEC4";
      case TINYGLTF_TYPE_MAT2: return "MAT2";
      case TINYGLTF_TYPE_MAT3: return "MAT3";
      case TINYGLTF_TYPE_MAT4: return "MAT4";
    }
    return "an unknown type";
  }

  // Validates accessor `a` (referenced from `ref`) and returns a bounds-checked view.
  View accessor(int a, const std::string& ref, int want_type, const std::vector<int>& want_components,
                const std::string& what) const {
    if (a < 0 || std::size_t(a) >= model_.accessors.size())
      fail(ref, "an index into /accessors (0 ≤ index < " + std::to_string(model_.accessors.size()) + ")");
    const tinygltf::Accessor& acc = model_.accessors[std::size_t(a)];
    const std::string ap = idx("/accessors", std::size_t(a));
    if (acc.sparse.isSparse) fail(ap + "/sparse", "a non-sparse accessor (sparse accessors are not supported)");
    if (acc.type != want_type ||
        std::find(want_components.begin(), want_components.end(), acc.componentType) == want_components.end()) {
      std::string comps;
      for (int c : want_components) {
        if (!comps.empty()) comps += " or ";
        switch (c) {
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: comps += "UNSIGNED_BYTE"; break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: comps += "UNSIGNED_SHORT"; break;
          case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: comps += "UNSIGNED_INT"; break;
          case TINYGLTF_COMPONENT_TYPE_FLOAT: comps += "FLOAT"; break;
          default: comps += std::to_string(c);
        }
      }
      fail(ap, what + " accessor of type " + type_name(want_type) + " with componentType " + comps + " (got " +
                   type_name(acc.type) + ", componentType " + std::to_string(acc.componentType) + ")");
    }
    if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && acc.normalized)
      fail(ap + "/normalized", "false for " + what);
    if (acc.count == 0) fail(ap + "/count", "count ≥ 1");
    if (acc.bufferView < 0)
      fail(ap, "a \"bufferView\" (accessors without one, all zeros, are not supported for " + what + ")");
    if (std::size_t(acc.bufferView) >= model_.bufferViews.size())
      fail(ap + "/bufferView", "an index into /bufferViews (0 ≤ index < " + std::to_string(model_.bufferViews.size()) + ")");
    const tinygltf::BufferView& bv = model_.bufferViews[std::size_t(acc.bufferView)];
    const std::string vp = idx("/bufferViews", std::size_t(acc.bufferView));
    if (bv.buffer < 0 || std::size_t(bv.buffer) >= model_.buffers.size())
      fail(vp + "/buffer", "an index into /buffers (0 ≤ index < " + std::to_string(model_.buffers.size()) + ")");
    const std::vector<unsigned char>& buf = model_.buffers[std::size_t(bv.buffer)].data;
    if (bv.byteOffset > buf.size() || bv.byteLength > buf.size() - bv.byteOffset)
      fail(vp, "byteOffset + byteLength (" + std::to_string(bv.byteOffset) + " + " + std::to_string(bv.byteLength) +
                   ") within buffer " + std::to_string(bv.buffer) + " (" + std::to_string(buf.size()) + " bytes)");
    const std::size_t csize = std::size_t(tinygltf::GetComponentSizeInBytes(std::uint32_t(acc.componentType)));
    const std::size_t ncomp = std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(acc.type)));
    const std::size_t elem = csize * ncomp;
    std::size_t stride = elem;
    if (bv.byteStride != 0) {
      if (bv.byteStride < elem || bv.byteStride % csize != 0 || bv.byteStride > 252)
        fail(vp + "/byteStride", "a byteStride ≥ " + std::to_string(elem) + ", ≤ 252, a multiple of " +
                                     std::to_string(csize) + " (got " + std::to_string(bv.byteStride) + ")");
      stride = bv.byteStride;
    }
    const std::size_t len = bv.byteLength;
    const bool fits = acc.byteOffset <= len && elem <= len - acc.byteOffset &&
                      acc.count - 1 <= (len - acc.byteOffset - elem) / stride;
    if (!fits)
      fail(ap, "byteOffset + (count − 1) × stride + element size (" + std::to_string(acc.byteOffset) + " + (" +
                   std::to_string(acc.count) + " − 1) × " + std::to_string(stride) + " + " + std::to_string(elem) +
                   ") within bufferView " + std::to_string(acc.bufferView) + " (" + std::to_string(len) + " bytes)");
    View v;
    v.data = buf.data() + bv.byteOffset + acc.byteOffset;
    v.stride = stride;
    v.count = acc.count;
    v.component_type = acc.componentType;
    return v;
  }

  static glm::vec3 read_vec3(const View& v, std::size_t i) {
    float f[3];
    std::memcpy(f, v.data + i * v.stride, sizeof f);
    return {f[0], f[1], f[2]};
  }

  static std::uint32_t read_index(const View& v, std::size_t i) {
    const unsigned char* p = v.data + i * v.stride;
    switch (v.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t x;
        std::memcpy(&x, p, 2);
        return x;
      }
      default: {
        std::uint32_t x;
        std::memcpy(&x, p, 4);
        return x;
      }
    }
  }

  // ---- meshes and materials ------------------------------------------------

  std::uint32_t mesh_for(std::size_t m, std::size_t p) {
    const auto key = std::make_pair(m, p);
    if (auto it = mesh_cache_.find(key); it != mesh_cache_.end()) return it->second;
    const tinygltf::Mesh& gm = model_.meshes[m];
    const tinygltf::Primitive& prim = gm.primitives[p];
    const std::string pp = idx(idx("/meshes", m) + "/primitives", p);
    if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
      static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP", "TRIANGLES", "TRIANGLE_STRIP",
                                    "TRIANGLE_FAN"};
      const std::string got = prim.mode >= 0 && prim.mode <= 6 ? names[prim.mode] : "an unknown mode";
      fail(pp + "/mode", "mode 4 (TRIANGLES); got " + std::to_string(prim.mode) + " (" + got + ")");
    }
    if (!prim.targets.empty())
      warn("morph targets of " + pp + " ignored: the base shape is used");

    Mesh mesh;
    mesh.name = (gm.name.empty() ? "mesh_" + std::to_string(m) : gm.name) +
                (gm.primitives.size() > 1 ? "/" + std::to_string(p) : std::string());
    auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) fail(pp + "/attributes", "a POSITION attribute");
    const View pos = accessor(pos_it->second, pp + "/attributes/POSITION", TINYGLTF_TYPE_VEC3,
                              {TINYGLTF_COMPONENT_TYPE_FLOAT}, "a POSITION");
    if (pos.count > std::size_t(std::numeric_limits<std::uint32_t>::max()))
      fail(idx("/accessors", std::size_t(pos_it->second)) + "/count", "fewer than 2^32 vertices");
    mesh.positions.resize(pos.count);
    for (std::size_t i = 0; i < pos.count; ++i) {
      const glm::vec3 x = read_vec3(pos, i);
      if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
        fail(idx("/accessors", std::size_t(pos_it->second)),
             "finite POSITION values (vertex " + std::to_string(i) + " is NaN or infinite; used by " + pp + ")");
      mesh.positions[i] = x;
    }
    if (auto n_it = prim.attributes.find("NORMAL"); n_it != prim.attributes.end()) {
      const View nrm = accessor(n_it->second, pp + "/attributes/NORMAL", TINYGLTF_TYPE_VEC3,
                                {TINYGLTF_COMPONENT_TYPE_FLOAT}, "a NORMAL");
      const std::string np = idx("/accessors", std::size_t(n_it->second));
      if (nrm.count != pos.count)
        fail(np + "/count", "as many normals as positions (" + std::to_string(pos.count) + ")");
      mesh.normals.resize(nrm.count);
      std::size_t degenerate = 0;
      for (std::size_t i = 0; i < nrm.count; ++i) {
        const glm::vec3 n = read_vec3(nrm, i);
        if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
          fail(np, "finite NORMAL values (normal " + std::to_string(i) + " is NaN or infinite; used by " + pp + ")");
        const float l = glm::length(n);
        if (!(l > 1e-12f)) ++degenerate;
        mesh.normals[i] = l > 1e-12f ? n / l : n;
      }
      if (degenerate) {
        warn(pp + ": " + std::to_string(degenerate) + " zero-length normal(s): normals dropped, flat shading used");
        mesh.normals.clear();
      }
    }
    read_texture_attributes(prim, pp, pos.count, mesh);
    if (prim.indices >= 0) {
      const View ind = accessor(prim.indices, pp + "/indices", TINYGLTF_TYPE_SCALAR,
                                {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                                "an index");
      if (ind.count % 3 != 0)
        fail(idx("/accessors", std::size_t(prim.indices)) + "/count",
             "a multiple of 3 indices for TRIANGLES (got " + std::to_string(ind.count) + ")");
      mesh.indices.resize(ind.count);
      for (std::size_t i = 0; i < ind.count; ++i) {
        const std::uint32_t k = read_index(ind, i);
        if (k >= pos.count)
          fail(pp + "/indices", "indices < " + std::to_string(pos.count) + " (the POSITION count); index " +
                                    std::to_string(i) + " is " + std::to_string(k));
        mesh.indices[i] = k;
      }
    } else {
      if (pos.count % 3 != 0)
        fail(idx("/accessors", std::size_t(pos_it->second)) + "/count",
             "a multiple of 3 vertices for non-indexed TRIANGLES (got " + std::to_string(pos.count) + ")");
      mesh.indices.resize(pos.count);
      for (std::size_t i = 0; i < pos.count; ++i) mesh.indices[i] = std::uint32_t(i);
    }
    if (mesh.tangents.empty() && uses_normal_map(prim.material)) generate_missing_tangents(mesh, pp);
    const std::uint32_t id = std::uint32_t(scene_.meshes.size());
    scene_.meshes.push_back(std::move(mesh));
    mesh_cache_.emplace(key, id);
    return id;
  }

  // TEXCOORD_0 and TANGENT, read when present (FLOAT only). Other texture
  // coordinate sets are left alone: a texture that uses one is warned about.
  void read_texture_attributes(const tinygltf::Primitive& prim, const std::string& pp, std::size_t count,
                               Mesh& mesh) const {
    if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
      const View uv = accessor(it->second, pp + "/attributes/TEXCOORD_0", TINYGLTF_TYPE_VEC2,
                               {TINYGLTF_COMPONENT_TYPE_FLOAT}, "a TEXCOORD_0");
      const std::string ap = idx("/accessors", std::size_t(it->second));
      if (uv.count != count) fail(ap + "/count", "as many TEXCOORD_0 as positions (" + std::to_string(count) + ")");
      mesh.uvs.resize(count);
      for (std::size_t i = 0; i < count; ++i) {
        float f[2];
        std::memcpy(f, uv.data + i * uv.stride, sizeof f);
        if (!std::isfinite(f[0]) || !std::isfinite(f[1]))
          fail(ap, "finite TEXCOORD_0 values (element " + std::to_string(i) + " is NaN or infinite)");
        mesh.uvs[i] = glm::vec2(f[0], f[1]);
      }
    }
    if (auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
      const View tv = accessor(it->second, pp + "/attributes/TANGENT", TINYGLTF_TYPE_VEC4,
                               {TINYGLTF_COMPONENT_TYPE_FLOAT}, "a TANGENT");
      const std::string ap = idx("/accessors", std::size_t(it->second));
      if (tv.count != count) fail(ap + "/count", "as many TANGENT as positions (" + std::to_string(count) + ")");
      mesh.tangents.resize(count);
      for (std::size_t i = 0; i < count; ++i) {
        float f[4];
        std::memcpy(f, tv.data + i * tv.stride, sizeof f);
        if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]) || (f[3] != 1.0f && f[3] != -1.0f))
          fail(ap, "TANGENT values with finite xyz and w = ±1 (element " + std::to_string(i) + ")");
        mesh.tangents[i] = glm::vec4(f[0], f[1], f[2], f[3]);
      }
    }
  }

  bool uses_normal_map(int material) const {
    return material >= 0 && std::size_t(material) < model_.materials.size() &&
           model_.materials[std::size_t(material)].normalTexture.index >= 0;
  }

  // glTF 2.0 (§3.7.2.1): without TANGENT, a normal-mapped primitive gets
  // MikkTSpace tangents (core/tangents.h), which needs normals and uvs.
  void generate_missing_tangents(Mesh& mesh, const std::string& pp) {
    if (mesh.normals.empty() || mesh.uvs.empty()) {
      warn(pp + ": normal map ignored: tangents need " +
           std::string(mesh.normals.empty() ? "NORMAL" : "TEXCOORD_0") + " and the primitive has none");
      return;
    }
    generate_tangents(mesh);
  }

  float finite_float(double v, const std::string& path) const {
    if (!finite_f32(v)) fail(path, "a finite number");
    return static_cast<float>(v);
  }

  static std::uint32_t wrap_mode(int gl_wrap) {
    switch (gl_wrap) {
      case 33071: return shader::TEXTURE_WRAP_CLAMP_TO_EDGE;
      case 33648: return shader::TEXTURE_WRAP_MIRRORED_REPEAT;
      default: return shader::TEXTURE_WRAP_REPEAT;  // 10497 (the schema check refused anything else)
    }
  }

  glm::vec2 vec2_of(const tinygltf::Value& v, const std::string& path) const {
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
      fail(path, "an array of 2 numbers");
    return {finite_float(v.Get(0).GetNumberAsDouble(), path + "/0"),
            finite_float(v.Get(1).GetNumberAsDouble(), path + "/1")};
  }

  // A material's textureInfo: the image (decoded once), the sampler's wrap
  // modes and KHR_texture_transform.
  TextureRef texture_ref(int index, int tex_coord, const tinygltf::ExtensionMap& ext, const std::string& path) {
    TextureRef ref;
    if (index < 0) return ref;
    if (std::size_t(index) >= model_.textures.size())
      fail(path + "/index", "an index into /textures (0 ≤ index < " + std::to_string(model_.textures.size()) + ")");
    const tinygltf::Texture& t = model_.textures[std::size_t(index)];
    const std::string tp = idx("/textures", std::size_t(index));
    if (t.source < 0) fail(tp, "a \"source\" image (textures without one are not supported)");
    if (std::size_t(t.source) >= model_.images.size())
      fail(tp + "/source", "an index into /images (0 ≤ index < " + std::to_string(model_.images.size()) + ")");
    for (const auto& [name, value] : t.extensions) warn(tp + ": extension " + name + " ignored; \"source\" used");
    ref.image = std::int32_t(image_for(t.source));
    if (t.sampler >= 0) {
      if (std::size_t(t.sampler) >= model_.samplers.size())
        fail(tp + "/sampler", "an index into /samplers (0 ≤ index < " + std::to_string(model_.samplers.size()) + ")");
      const tinygltf::Sampler& sm = model_.samplers[std::size_t(t.sampler)];
      ref.wrap_s = wrap_mode(sm.wrapS);
      ref.wrap_t = wrap_mode(sm.wrapT);
    }
    if (auto it = ext.find("KHR_texture_transform"); it != ext.end()) {
      const tinygltf::Value& x = it->second;
      const std::string xp = path + "/extensions/KHR_texture_transform";
      if (!x.IsObject()) fail(xp, "an object");
      if (x.Has("offset")) ref.offset = vec2_of(x.Get("offset"), xp + "/offset");
      if (x.Has("scale")) ref.scale = vec2_of(x.Get("scale"), xp + "/scale");
      if (x.Has("rotation")) {
        if (!x.Get("rotation").IsNumber()) fail(xp + "/rotation", "a number (radians)");
        ref.rotation = finite_float(x.Get("rotation").GetNumberAsDouble(), xp + "/rotation");
      }
      if (x.Has("texCoord")) {
        if (!x.Get("texCoord").IsInt()) fail(xp + "/texCoord", "an integer ≥ 0");
        tex_coord = x.Get("texCoord").GetNumberAsInt();
      }
    }
    for (const auto& [name, value] : ext)
      if (name != "KHR_texture_transform") warn(path + ": extension " + name + " ignored");
    if (tex_coord != 0) warn(path + ": texCoord " + std::to_string(tex_coord) + " is not supported; TEXCOORD_0 used");
    return ref;
  }

  std::uint32_t image_for(int gltf_image) {
    if (auto it = image_cache_.find(gltf_image); it != image_cache_.end()) return it->second;
    tinygltf::Image& gi = model_.images[std::size_t(gltf_image)];
    const std::string ip = idx("/images", std::size_t(gltf_image));
    if (gi.image.empty()) fail(ip, "an image with data (a uri or a bufferView)");
    TextureImage out;
    out.name = gi.name.empty() ? "image_" + std::to_string(gltf_image) : gi.name;
    std::string why;
    if (!decode_texture_image(gi.image.data(), gi.image.size(), out, why)) fail(ip, why);
    std::vector<unsigned char>().swap(gi.image);  // the encoded bytes are no longer needed
    const std::uint32_t id = std::uint32_t(scene_.images.size());
    scene_.images.push_back(std::move(out));
    image_cache_.emplace(gltf_image, id);
    return id;
  }

  float factor(double v, const std::string& path, double lo, double hi) const {
    if (!std::isfinite(v) || v < lo || v > hi)
      fail(path, "a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (got " + std::to_string(v) + ")");
    return static_cast<float>(v);
  }

  glm::vec3 color3(const std::vector<double>& v, const std::string& path, double hi, std::size_t want_len) const {
    if (v.size() != want_len) fail(path, "an array of " + std::to_string(want_len) + " numbers");
    glm::vec3 c;
    for (int i = 0; i < 3; ++i) c[i] = factor(v[std::size_t(i)], idx(path, std::size_t(i)), 0.0, hi);
    return c;
  }

  static const tinygltf::Value* ext_value(const tinygltf::ExtensionMap& ext, const std::string& e, const char* key) {
    auto it = ext.find(e);
    if (it == ext.end() || !it->second.IsObject() || !it->second.Has(key)) return nullptr;
    return &it->second.Get(key);
  }

  double ext_number(const tinygltf::ExtensionMap& ext, const std::string& e, const char* key, double dflt,
                    const std::string& path) const {
    const tinygltf::Value* v = ext_value(ext, e, key);
    if (!v) return dflt;
    if (!v->IsNumber()) fail(path + "/extensions/" + e + "/" + key, "a number");
    return v->GetNumberAsDouble();
  }

  std::uint32_t material_for(int mi, const std::string& ref) {
    if (auto it = material_cache_.find(mi); it != material_cache_.end()) return it->second;
    Material out;
    if (mi < 0) {
      // The glTF default material (spec §3.9.6).
      out.name = "gltf_default";
      out.base_color = glm::vec3(1.0f);
      out.metallic = 1.0f;
      out.perceptual_roughness = 1.0f;
      warn(ref + " has no material: the glTF default material (white, metallic 1, roughness 1) is used");
    } else {
      if (std::size_t(mi) >= model_.materials.size())
        fail(ref + "/material", "an index into /materials (0 ≤ index < " + std::to_string(model_.materials.size()) + ")");
      const tinygltf::Material& gm = model_.materials[std::size_t(mi)];
      const std::string mp = idx("/materials", std::size_t(mi));
      out.name = gm.name.empty() ? "material_" + std::to_string(mi) : gm.name;
      const tinygltf::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
      const std::string pp = mp + "/pbrMetallicRoughness";
      if (pbr.baseColorFactor.size() != 4) fail(pp + "/baseColorFactor", "an array of 4 numbers");
      out.base_color = color3(pbr.baseColorFactor, pp + "/baseColorFactor", 1.0, 4);
      const float alpha = factor(pbr.baseColorFactor[3], pp + "/baseColorFactor/3", 0.0, 1.0);
      out.metallic = factor(pbr.metallicFactor, pp + "/metallicFactor", 0.0, 1.0);
      out.perceptual_roughness = factor(pbr.roughnessFactor, pp + "/roughnessFactor", 0.0, 1.0);
      glm::vec3 emissive(0.0f);
      if (!gm.emissiveFactor.empty()) emissive = color3(gm.emissiveFactor, mp + "/emissiveFactor", 1.0, 3);
      const double strength = ext_number(gm.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0, mp);
      if (!finite_f32(strength) || strength < 0)
        fail(mp + "/extensions/KHR_materials_emissive_strength/emissiveStrength", "a finite number ≥ 0");
      out.emissive = emissive * static_cast<float>(strength);
      // Reflectance as Bevy's glTF loader sets it: specularFactor × 0.5
      // (v0.19.0:crates/bevy_gltf/src/loader/mod.rs:1483, the same at
      // v0.18.0:crates/bevy_gltf/src/loader/mod.rs:1417), so F0 = 0.16 r² =
      // 0.04 specularFactor². The loader reads KHR_materials_ior for
      // transmission only (v0.19.0:crates/bevy_gltf/src/loader/mod.rs:1399,
      // 1450), never for F0.
      const double spec = ext_number(gm.extensions, "KHR_materials_specular", "specularFactor", 1.0, mp);
      if (!std::isfinite(spec) || spec < 0 || spec > 1)
        fail(mp + "/extensions/KHR_materials_specular/specularFactor", "a number in [0, 1]");
      const double ior = ext_number(gm.extensions, "KHR_materials_ior", "ior", 1.5, mp);
      if (!std::isfinite(ior) || !(ior == 0.0 || ior >= 1.0))
        fail(mp + "/extensions/KHR_materials_ior/ior", "0 or a number ≥ 1");
      if (ior != 1.5) warn(mp + ": KHR_materials_ior ior ignored (Bevy's loader takes F0 from specularFactor alone)");
      out.reflectance = static_cast<float>(spec * 0.5);
      if (const tinygltf::Value* sc = ext_value(gm.extensions, "KHR_materials_specular", "specularColorFactor")) {
        bool white = sc->IsArray() && sc->ArrayLen() == 3;
        for (std::size_t i = 0; white && i < 3; ++i)
          white = sc->Get(int(i)).IsNumber() && sc->Get(int(i)).GetNumberAsDouble() == 1.0;
        if (!white) warn(mp + ": KHR_materials_specular specularColorFactor ignored (white assumed)");
      }
      if (ext_value(gm.extensions, "KHR_materials_specular", "specularTexture") ||
          ext_value(gm.extensions, "KHR_materials_specular", "specularColorTexture"))
        warn(mp + ": specular textures ignored; factors used");
      for (const auto& [name, value] : gm.extensions)
        if (name != "KHR_materials_emissive_strength" && name != "KHR_materials_specular" && name != "KHR_materials_ior")
          warn(mp + ": extension " + name + " ignored");
      out.base_color_texture = texture_ref(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                           pbr.baseColorTexture.extensions, pp + "/baseColorTexture");
      out.metallic_roughness_texture =
          texture_ref(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                      pbr.metallicRoughnessTexture.extensions, pp + "/metallicRoughnessTexture");
      out.emissive_texture = texture_ref(gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
                                         gm.emissiveTexture.extensions, mp + "/emissiveTexture");
      out.normal_texture = texture_ref(gm.normalTexture.index, gm.normalTexture.texCoord,
                                       gm.normalTexture.extensions, mp + "/normalTexture");
      if (out.normal_texture.present())
        out.normal_texture.normal_scale = finite_float(gm.normalTexture.scale, mp + "/normalTexture/scale");
      if (gm.occlusionTexture.index >= 0)
        warn(mp + " (" + out.name + "): occlusionTexture ignored: a path tracer needs no ambient occlusion");
      if (gm.alphaMode != "OPAQUE" || alpha < 1.0f)
        warn(mp + " (" + out.name + "): alphaMode " + gm.alphaMode + " with alpha " + std::to_string(alpha) +
             " ignored: the surface is opaque");
    }
    const std::uint32_t id = std::uint32_t(scene_.materials.size());
    scene_.materials.push_back(std::move(out));
    material_cache_.emplace(mi, id);
    return id;
  }

  // ---- nodes --------------------------------------------------------------

  glm::dmat4 local_transform(const tinygltf::Node& n, const std::string& np) {
    auto check = [&](const std::vector<double>& v, const char* key, std::size_t len) {
      if (v.empty()) return false;
      if (v.size() != len) fail(np + "/" + key, "an array of " + std::to_string(len) + " numbers");
      for (std::size_t i = 0; i < len; ++i)
        if (!finite_f32(v[i]))
          fail(np + "/" + key, std::string("finite numbers representable as 32-bit floats (element ") +
                                   std::to_string(i) + " is " + std::to_string(v[i]) + ")");
      return true;
    };
    if (check(n.matrix, "matrix", 16)) {
      glm::dmat4 m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[std::size_t(c * 4 + r)];  // column-major
      if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
        fail(np + "/matrix", "an affine matrix (last row 0, 0, 0, 1)");
      return m;
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (check(n.translation, "translation", 3))
      t = glm::translate(glm::dmat4(1.0), glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
    if (check(n.rotation, "rotation", 4)) {
      glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF: x, y, z, w
      const double len = glm::length(q);
      if (!(len > 1e-6)) fail(np + "/rotation", "a unit quaternion (got length " + std::to_string(len) + ")");
      if (std::fabs(len - 1.0) > 1e-3)
        warn(np + "/rotation: quaternion of length " + std::to_string(len) + " normalised");
      r = glm::mat4_cast(q / len);
    }
    if (check(n.scale, "scale", 3)) s = glm::scale(glm::dmat4(1.0), glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
    return t * r * s;
  }

  std::string node_name(std::size_t n) const {
    return model_.nodes[n].name.empty() ? "node_" + std::to_string(n) : model_.nodes[n].name;
  }

  void walk_scene() {
    int si = model_.defaultScene;
    if (model_.scenes.empty()) fail("/scenes", "at least one scene");
    if (si < 0) {
      warn("no default scene (\"scene\"): scene 0 is used");
      si = 0;
    } else if (std::size_t(si) >= model_.scenes.size()) {
      fail("/scene", "an index into /scenes (0 ≤ index < " + std::to_string(model_.scenes.size()) + ")");
    }
    scene_path_ = idx("/scenes", std::size_t(si));
    const tinygltf::Scene& gs = model_.scenes[std::size_t(si)];
    if (!gs.name.empty()) scene_.name = gs.name;

    // Depth first, pre-order, children in order, with an explicit stack (no
    // recursion depth for a hostile file to exhaust).
    struct Item {
      int node;
      std::string ref;  // the JSON pointer that reached it
      glm::dmat4 parent;
    };
    std::vector<Item> stack;
    for (std::size_t k = gs.nodes.size(); k-- > 0;) stack.push_back({gs.nodes[k], idx(scene_path_ + "/nodes", k), glm::dmat4(1.0)});
    std::vector<std::string> reached_from(model_.nodes.size());
    std::vector<char> reached(model_.nodes.size(), 0);
    while (!stack.empty()) {
      Item it = std::move(stack.back());
      stack.pop_back();
      if (it.node < 0 || std::size_t(it.node) >= model_.nodes.size())
        fail(it.ref, "an index into /nodes (0 ≤ index < " + std::to_string(model_.nodes.size()) + ")");
      const std::size_t n = std::size_t(it.node);
      const std::string np = idx("/nodes", n);
      if (reached[n])
        fail(it.ref, "a node graph that is a tree: " + np + " is reached again (first from " + reached_from[n] +
                         "); cycles and shared nodes are not allowed");
      reached[n] = 1;
      reached_from[n] = it.ref;
      const tinygltf::Node& node = model_.nodes[n];
      const glm::dmat4 world = it.parent * local_transform(node, np);
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          if (!finite_f32(world[c][r]))
            fail(np, "a finite world transform (composed parent → child, it overflows 32-bit floats)");
      visit(n, np, world);
      for (std::size_t k = node.children.size(); k-- > 0;)
        stack.push_back({node.children[k], np + "/children/" + std::to_string(k), world});
    }
  }

  void visit(std::size_t n, const std::string& np, const glm::dmat4& world) {
    const tinygltf::Node& node = model_.nodes[n];
    const glm::mat4 wf(world);
    if (node.skin >= 0) warn(np + ": skin ignored (static bind pose: the node's transform is used)");
    if (!node.weights.empty()) warn(np + ": morph target weights ignored");
    if (node.mesh >= 0) {
      if (std::size_t(node.mesh) >= model_.meshes.size())
        fail(np + "/mesh", "an index into /meshes (0 ≤ index < " + std::to_string(model_.meshes.size()) + ")");
      const std::size_t m = std::size_t(node.mesh);
      const tinygltf::Mesh& gm = model_.meshes[m];
      const double det = glm::determinant(glm::dmat3(world));
      if (det < 0.0)
        warn(np + ": mirroring transform (negative determinant); glTF then makes clockwise faces the front, "
                  "the harness keeps each mesh's counter-clockwise front faces");
      for (std::size_t p = 0; p < gm.primitives.size(); ++p) {
        const std::string pp = idx(idx("/meshes", m) + "/primitives", p);
        Instance inst;
        inst.name = node_name(n) + (gm.primitives.size() > 1 ? "/" + std::to_string(p) : std::string());
        inst.mesh = mesh_for(m, p);
        inst.material = material_for(gm.primitives[p].material, pp);
        inst.transform = wf;
        if (scene_.find_instance(inst.name))
          warn("instance name \"" + inst.name + "\" (" + np + ") is used twice: events naming it reach the first");
        check_emitter(inst, np);
        scene_.instances.push_back(std::move(inst));
      }
    }
    if (node.camera >= 0) {
      if (std::size_t(node.camera) >= model_.cameras.size())
        fail(np + "/camera", "an index into /cameras (0 ≤ index < " + std::to_string(model_.cameras.size()) + ")");
      const tinygltf::Camera& cam = model_.cameras[std::size_t(node.camera)];
      const std::string cp = idx("/cameras", std::size_t(node.camera));
      if (cam.type != "perspective") {
        warn(np + ": " + cam.type + " camera " + cp + " ignored (only perspective cameras are used)");
      } else if (camera_found_) {
        warn(np + ": camera ignored (the first one reached, " + camera_node_ + ", is used)");
      } else {
        const double yfov = cam.perspective.yfov;
        if (!std::isfinite(yfov) || yfov <= 0.0 || yfov >= 3.14159)
          fail(cp + "/perspective/yfov", "a vertical field of view in radians in (0, π)");
        const glm::dvec3 pos(world[3]);
        const glm::dvec3 fwd = glm::dmat3(world) * glm::dvec3(0, 0, -1);
        const glm::dvec3 up = glm::dmat3(world) * glm::dvec3(0, 1, 0);
        const glm::dvec3 side = glm::cross(fwd, up);
        if (!(glm::length(fwd) > 1e-9) || !(glm::length(up) > 1e-9) ||
            !(glm::length(side) > 1e-9 * glm::length(fwd) * glm::length(up)))
          fail(np, "a camera node whose transform keeps −Z and +Y apart (it is singular)");
        scene_.camera.position = glm::vec3(pos);
        scene_.camera.target = glm::vec3(pos + glm::normalize(fwd));
        scene_.camera.up = glm::vec3(glm::normalize(glm::cross(side, fwd)));
        scene_.camera.vertical_fov_degrees = static_cast<float>(yfov * 180.0 / 3.14159265358979323846);
        camera_found_ = true;
        camera_node_ = np;
      }
    }
    if (auto e = node.extensions.find("KHR_lights_punctual"); e != node.extensions.end()) {
      const std::string lp = np + "/extensions/KHR_lights_punctual/light";
      if (!e->second.IsObject() || !e->second.Has("light") || !e->second.Get("light").IsInt())
        fail(lp, "a light index");
      const int li = e->second.Get("light").GetNumberAsInt();
      if (li < 0 || std::size_t(li) >= model_.lights.size())
        fail(lp, "an index into /extensions/KHR_lights_punctual/lights (0 ≤ index < " +
                     std::to_string(model_.lights.size()) + ")");
      light(n, np, std::size_t(li), world);
    }
  }

  void check_emitter(const Instance& inst, const std::string& np) {
    const Material& mat = scene_.materials[inst.material];
    if (!(mat.emissive.x > 0 || mat.emissive.y > 0 || mat.emissive.z > 0)) return;
    const Mesh& mesh = scene_.meshes[inst.mesh];
    std::size_t zero = 0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
      glm::dvec3 v[3];
      for (int k = 0; k < 3; ++k)
        v[k] = glm::dvec3(glm::dmat4(inst.transform) * glm::dvec4(glm::dvec3(mesh.positions[mesh.indices[3 * t + k]]), 1.0));
      const double area = 0.5 * glm::length(glm::cross(v[1] - v[0], v[2] - v[0]));
      if (!(area > 1e-12)) ++zero;
    }
    // An emitter with no area at all cannot emit: the scene would silently
    // lose a light, so that is bad input. A few degenerate triangles in a
    // real emitter are only stated (the renderers never pick them).
    if (zero == mesh.triangle_count())
      fail(np, "an emitter with non-zero area: all " + std::to_string(zero) + " emissive triangles of \"" + inst.name +
                   "\" have zero area");
    if (zero)
      warn(np + " (\"" + inst.name + "\"): " + std::to_string(zero) + " of " + std::to_string(mesh.triangle_count()) +
           " emissive triangles have zero area: kept in the mesh, never sampled as lights");
  }

  void light(std::size_t n, const std::string& np, std::size_t li, const glm::dmat4& world) {
    const tinygltf::Light& gl = model_.lights[li];
    const std::string lp = idx("/extensions/KHR_lights_punctual/lights", li);
    if (gl.type != "directional") {
      warn(np + ": " + (gl.type.empty() ? std::string("untyped") : gl.type) + " light " + lp +
           " ignored (only directional lights are modelled)");
      return;
    }
    DirectionalLight d;
    d.name = !model_.nodes[n].name.empty() ? model_.nodes[n].name : !gl.name.empty() ? gl.name : node_name(n);
    const glm::dvec3 z = glm::dmat3(world) * glm::dvec3(0, 0, 1);
    if (!(glm::length(z) > 1e-9)) fail(np, "a light node whose transform keeps +Z (it is singular)");
    d.direction = glm::vec3(glm::normalize(z));
    if (!gl.color.empty()) d.color = color3(gl.color, lp + "/color", std::numeric_limits<float>::max(), 3);
    if (!finite_f32(gl.intensity) || gl.intensity < 0) fail(lp + "/intensity", "a finite number ≥ 0 (lux)");
    d.illuminance = static_cast<float>(gl.intensity);
    d.angular_radius = 0.00465f;
    if (gl.extras.IsObject() && gl.extras.Has("angular_radius")) {
      const tinygltf::Value& a = gl.extras.Get("angular_radius");
      if (!a.IsNumber() || !(a.GetNumberAsDouble() >= 0.0) || !(a.GetNumberAsDouble() < 1.5707963))
        fail(lp + "/extras/angular_radius", "an angle in radians in [0, π/2)");
      d.angular_radius = static_cast<float>(a.GetNumberAsDouble());
    }
    if (scene_.find_directional_light(d.name))
      warn("directional light name \"" + d.name + "\" (" + np + ") is used twice: events naming it reach the first");
    scene_.directional_lights.push_back(std::move(d));
  }

  std::filesystem::path file_;
  std::string fname_;
  FsContext fs_;
  tinygltf::Model model_;
  Scene scene_;
  std::string scene_path_ = "/scenes/0";
  std::map<std::pair<std::size_t, std::size_t>, std::uint32_t> mesh_cache_;
  std::map<int, std::uint32_t> material_cache_;
  std::map<int, std::uint32_t> image_cache_;
  bool camera_found_ = false;
  std::string camera_node_;
};

}  // namespace

Scene import_gltf(const std::filesystem::path& file) { return Importer(file).run(); }

}  // namespace gi
