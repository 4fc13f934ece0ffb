// Material textures: the shared lookup (core/shared/texture_sampling.h) on a
// known texel pattern, KHR_texture_transform against its specification's
// example, each glTF wrap mode at known pixels of a GPU G-buffer, and the
// importer's handling of textures.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

#include <stb/stb_image_write.h>

#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/scene_flatten.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "tests/gltf_fixture.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;
using gi::test::json;
namespace sh = gi::shader;

// A 4×4 pattern whose every texel differs: R grows along x, G along y.
constexpr int kSide = 4;
glm::u8vec4 pattern_texel(int x, int y) { return {std::uint8_t(30 + 60 * x), std::uint8_t(20 + 70 * y), 200, 255}; }

std::vector<unsigned char> pattern_png() {
  std::vector<unsigned char> rgba;
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      const glm::u8vec4 t = pattern_texel(x, y);
      rgba.insert(rgba.end(), {t.x, t.y, t.z, t.w});
    }
  std::vector<unsigned char> png;
  stbi_write_png_to_func([](void* out, void* data, int size) {
    auto* v = static_cast<std::vector<unsigned char>*>(out);
    v->insert(v->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
  }, &png, kSide, kSide, 4, rgba.data(), kSide * 4);
  return png;
}

// The sRGB transfer function, written here from its definition (not the
// shared header's) so the test does not check the code against itself.
float srgb_decoded(std::uint8_t c) {
  const double x = c / 255.0;
  return float(x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4));
}
glm::vec3 linear_texel(int x, int y) {
  const glm::u8vec4 t = pattern_texel(x, y);
  return {srgb_decoded(t.x), srgb_decoded(t.y), srgb_decoded(t.z)};
}

// The scene's texels as the shared code reads them.
struct TexelSource {
  gi::FlatGeometry geometry;
  glm::vec4 at(sh::GpuTextureSlot slot, glm::vec2 uv) const {
    const sh::GpuTextureImage image = geometry.texture_images.at(slot.image_wrap.x);
    const sh::BilinearFootprint f = sh::bilinear_footprint(image, slot, sh::texture_transform(slot, uv));
    auto t = [&](unsigned i) { return sh::decode_texel(geometry.texels.at(i), false); };
    return sh::bilinear_blend(t(f.texel.x), t(f.texel.y), t(f.texel.z), t(f.texel.w), f.weight);
  }
};

// One material with the pattern as its base colour, through flatten_* (the
// path both renderers' data takes).
struct PatternScene {
  gi::Scene scene;
  gi::FlatGeometry geometry;
  gi::FlatInstances flat;
  explicit PatternScene(gi::TextureRef ref) {
    gi::TextureImage image;
    image.width = image.height = kSide;
    for (int y = 0; y < kSide; ++y)
      for (int x = 0; x < kSide; ++x) {
        const glm::u8vec4 t = pattern_texel(x, y);
        image.rgba.insert(image.rgba.end(), {t.x, t.y, t.z, t.w});
      }
    scene.images.push_back(image);
    gi::Material m;
    ref.image = 0;
    m.base_color_texture = ref;
    scene.materials.push_back(m);
    gi::Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2};
    scene.meshes.push_back(mesh);
    scene.instances.push_back(gi::Instance{"tri", 0, 0});
    geometry = gi::flatten_geometry(scene);
    flat = gi::flatten_instances(scene, geometry);
  }
  sh::GpuTextureSlot slot() const { return flat.material_textures.at(0).slots[sh::TEXTURE_SLOT_BASE_COLOR]; }
};

glm::vec3 raw_texel(int x, int y) { return glm::vec3(pattern_texel(x, y)) / 255.0f; }

TEST(TextureSampling, TexelCentresReadTheirTexelInEveryWrapMode) {
  // Texel i's centre is u = (i + ½)/4; i runs over three periods. Expected
  // columns, from glTF's definitions of the modes.
  const std::vector<std::pair<std::uint32_t, std::vector<int>>> cases = {
      {sh::TEXTURE_WRAP_REPEAT, {0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3}},
      {sh::TEXTURE_WRAP_CLAMP_TO_EDGE, {0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3}},
      {sh::TEXTURE_WRAP_MIRRORED_REPEAT, {3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0}},
  };
  for (const auto& [mode, columns] : cases) {
    gi::TextureRef ref;
    ref.wrap_s = ref.wrap_t = mode;
    PatternScene s(ref);
    const TexelSource texels{s.geometry};
    for (int i = -4; i < 8; ++i) {
      const glm::vec2 uv((i + 0.5f) / kSide, (1 + 0.5f) / kSide);
      const glm::vec3 got(texels.at(s.slot(), uv));
      const glm::vec3 want = raw_texel(columns[std::size_t(i + 4)], 1);
      EXPECT_LT(glm::length(got - want), 1e-5f) << "mode " << mode << " texel " << i;
    }
  }
}

TEST(TextureSampling, BilinearBlendsTheFourNearestTexels) {
  PatternScene s(gi::TextureRef{});
  const TexelSource texels{s.geometry};
  // Between texels (1, 2) and (2, 3), a quarter of the way in x and half in y.
  const glm::vec2 uv((1.5f + 0.25f) / kSide, (2.5f + 0.5f) / kSide);
  const glm::vec3 top = glm::mix(raw_texel(1, 2), raw_texel(2, 2), 0.25f);
  const glm::vec3 bottom = glm::mix(raw_texel(1, 3), raw_texel(2, 3), 0.25f);
  EXPECT_LT(glm::length(glm::vec3(texels.at(s.slot(), uv)) - glm::mix(top, bottom, 0.5f)), 1e-5f);
}

TEST(TextureSampling, TextureTransformFollowsTheSpecificationsExample) {
  // KHR_texture_transform's README: offset [0, 1], rotation π/2, scale ½
  // "utilizes only the lower left quadrant of the source image, rotated
  // clockwise 90°": texels x 0-1, y 2-3 of the 4×4 pattern (rows run down),
  // uv's u along the quadrant's rows upwards, v along its columns.
  gi::TextureRef ref;
  ref.offset = {0.0f, 1.0f};
  ref.rotation = 1.57079632679f;
  ref.scale = {0.5f, 0.5f};
  PatternScene s(ref);
  const TexelSource texels{s.geometry};
  const std::vector<std::pair<glm::vec2, glm::ivec2>> cases = {
      {{0.25f, 0.25f}, {0, 3}}, {{0.75f, 0.25f}, {0, 2}}, {{0.25f, 0.75f}, {1, 3}}, {{0.75f, 0.75f}, {1, 2}}};
  for (const auto& [uv, texel] : cases)
    EXPECT_LT(glm::length(glm::vec3(texels.at(s.slot(), uv)) - raw_texel(texel.x, texel.y)), 1e-5f)
        << "uv " << uv.x << "," << uv.y;
}

TEST(TextureSampling, SrgbIsDecodedPerTexelBeforeFiltering) {
  for (int c : {0, 10, 11, 128, 200, 255})
    EXPECT_NEAR(sh::srgb_to_linear(float(c) / 255.0f), srgb_decoded(std::uint8_t(c)), 1e-6f) << c;
  // Halfway between black and white: the mean of the decoded texels (0.5),
  // not the decoded mean (0.21).
  const std::uint32_t black = 0xff000000u, white = 0xffffffffu;
  const glm::vec4 mid = sh::bilinear_blend(sh::decode_texel(black, true), sh::decode_texel(white, true),
                                           sh::decode_texel(black, true), sh::decode_texel(white, true), {0.5f, 0.0f});
  EXPECT_NEAR(mid.x, 0.5f, 1e-6f);
}

// ---- through the importer and the GPU ------------------------------------

// A quad filling a 90° camera's view at distance 1, its uv running 0 → 2
// left to right and top to bottom: pixel (x, y) of an 8×8 image sees
// uv ((x + ½)/4, (y + ½)/4), a texel centre of the 4×4 pattern, in two
// periods, so the second shows the wrap mode.
std::string quad_gltf(const fs::path& dir, const std::string& name, int wrap_s, int wrap_t, const json& transform) {
  std::vector<float> positions{-1, 1, -1, 1, 1, -1, 1, -1, -1, -1, -1, -1};
  std::vector<float> normals{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  std::vector<float> uvs{0, 0, 2, 0, 2, 2, 0, 2};
  std::vector<std::uint16_t> indices{0, 2, 1, 0, 3, 2};
  std::vector<unsigned char> b;
  gi::test::append(b, positions);
  gi::test::append(b, normals);
  gi::test::append(b, uvs);
  gi::test::append(b, indices);
  json base_color = {{"index", 0}};
  if (!transform.is_null()) base_color["extensions"] = {{"KHR_texture_transform", transform}};
  json doc = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", json::array({"KHR_texture_transform"})},
      {"scene", 0},
      {"scenes", json::array({{{"nodes", {0, 1}}}})},
      {"nodes", json::array({{{"name", "quad"}, {"mesh", 0}}, {{"name", "camera"}, {"camera", 0}}})},
      {"cameras", json::array({{{"type", "perspective"},
                                {"perspective", {{"yfov", 1.5707963267948966}, {"znear", 0.01}, {"aspectRatio", 1.0}}}}})},
      {"meshes", json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}},
                                                            {"indices", 3}, {"material", 0}}})}}})},
      {"materials", json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", base_color}, {"metallicFactor", 0.0}}}}})},
      {"textures", json::array({{{"source", 0}, {"sampler", 0}}})},
      {"samplers", json::array({{{"wrapS", wrap_s}, {"wrapT", wrap_t}}})},
      {"images", json::array({{{"uri", "data:image/png;base64," + gi::test::base64(pattern_png())}}})},
      {"buffers", json::array({{{"byteLength", b.size()}, {"uri", "data:application/octet-stream;base64," + gi::test::base64(b)}}})},
      {"bufferViews", json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                                   {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 48}},
                                   {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
                                   {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 12}}})},
      {"accessors", json::array({{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                                  {"min", {-1, -1, -1}}, {"max", {1, 1, -1}}},
                                 {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                                 {{"bufferView", 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                                 {{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}})},
  };
  const fs::path file = dir / (name + ".gltf");
  std::ofstream(file) << doc.dump();
  return file.string();
}

class TexturedGpu : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    device_ = std::make_unique<gi::gpu::Device>(std::nullopt, gi::test::test_backend());
    compiler_ = std::make_unique<gi::gpu::ShaderCompiler>(fs::path(::testing::TempDir()) / "giharness-texture-test-cache");
  }
  static void TearDownTestSuite() {
    compiler_.reset();
    device_.reset();
  }
  // The G-buffer's albedo of the imported quad, 8×8.
  static gi::Image albedo(const std::string& file) {
    const gi::Scene scene = gi::import_gltf(file);
    const gi::FlatGeometry geometry = gi::flatten_geometry(scene);
    const gi::FlatInstances flat = gi::flatten_instances(scene, geometry);
    gi::gpu::Renderer r(*device_, *compiler_, geometry, {8, 8, true, false});
    r.update_scene(flat, scene.visible_instances());
    gi::FrameConstants f{};
    f.camera = gi::make_gpu_camera(scene.camera, 8, 8);
    f.previous_camera = f.camera;
    f.resolution_frame = glm::uvec4(8, 8, 0, 1);
    f.counts = glm::uvec4(std::uint32_t(flat.lights.size()), flat.directional_light_count, 1, 0);
    r.render_frame(f);
    return r.gbuffer_layer("albedo");
  }
  static fs::path dir() {
    fs::path d = fs::path(::testing::TempDir()) / "giharness-texture-test";
    fs::create_directories(d);
    return d;
  }
  static std::unique_ptr<gi::gpu::Device> device_;
  static std::unique_ptr<gi::gpu::ShaderCompiler> compiler_;
};
std::unique_ptr<gi::gpu::Device> TexturedGpu::device_;
std::unique_ptr<gi::gpu::ShaderCompiler> TexturedGpu::compiler_;

// Column (or row) of the texel pixel i shows in the quad's two periods.
int wrapped(int i, int gl_wrap) {
  if (gl_wrap == 33071) return std::min(i, kSide - 1);            // CLAMP_TO_EDGE
  if (gl_wrap == 33648) return i < kSide ? i : 2 * kSide - 1 - i;  // MIRRORED_REPEAT
  return i % kSide;                                                // REPEAT
}

TEST_F(TexturedGpu, EachWrapModeShowsItsTexelsAtKnownPixels) {
  for (const auto& [s, t] : std::vector<std::pair<int, int>>{{10497, 10497}, {33071, 33648}, {33648, 33071}}) {
    const gi::Image a = albedo(quad_gltf(dir(), "wrap_" + std::to_string(s), s, t, nullptr));
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const glm::vec3 want = linear_texel(wrapped(x, s), wrapped(y, t));
        EXPECT_LT(glm::length(a.pixels[std::size_t(y * 8 + x)] - want), 2e-3f)
            << "wrap " << s << "/" << t << " pixel " << x << "," << y;
      }
  }
}

TEST_F(TexturedGpu, TextureTransformRotatesTheImageAtKnownPixels) {
  // offset [0, 1], rotation π/2: uv' = (v, 1 − u), so pixel (x, y) shows
  // texel (y mod 4, (3 − x) mod 4) under REPEAT.
  const gi::Image a = albedo(quad_gltf(dir(), "transform", 10497, 10497,
                                       json{{"offset", {0.0, 1.0}}, {"rotation", 1.5707963267948966}}));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const glm::vec3 want = linear_texel(y % kSide, ((3 - x) % kSide + kSide) % kSide);
      EXPECT_LT(glm::length(a.pixels[std::size_t(y * 8 + x)] - want), 2e-3f) << "pixel " << x << "," << y;
    }
}

TEST(GltfTextures, ImportKeepsTheSamplerTransformAndDecodesTheImageOnce) {
  const fs::path d = fs::path(::testing::TempDir()) / "giharness-texture-import";
  fs::create_directories(d);
  const gi::Scene s = gi::import_gltf(quad_gltf(d, "import", 33648, 33071,
                                                json{{"offset", {0.25, 0.5}}, {"rotation", 0.5}, {"scale", {2.0, 3.0}}}));
  ASSERT_EQ(s.images.size(), 1u);
  EXPECT_EQ(s.images[0].width, 4u);
  EXPECT_EQ(s.images[0].rgba.size(), 64u);
  const gi::TextureRef& t = s.materials.at(0).base_color_texture;
  EXPECT_EQ(t.image, 0);
  EXPECT_EQ(t.wrap_s, sh::TEXTURE_WRAP_MIRRORED_REPEAT);
  EXPECT_EQ(t.wrap_t, sh::TEXTURE_WRAP_CLAMP_TO_EDGE);
  EXPECT_EQ(t.offset, glm::vec2(0.25f, 0.5f));
  EXPECT_EQ(t.rotation, 0.5f);
  EXPECT_EQ(t.scale, glm::vec2(2.0f, 3.0f));
  EXPECT_EQ(s.meshes.at(0).uvs.size(), 4u);
  EXPECT_TRUE(s.meshes.at(0).tangents.empty());  // no normal map: none generated
}

TEST(GltfTextures, AnUndecodableImageIsBadInputAtItsPath) {
  gi::test::TinyGltf tiny;
  json doc = tiny.doc();
  doc["images"] = json::array({{{"uri", "data:image/png;base64," + gi::test::base64({1, 2, 3, 4, 5, 6, 7, 8})}}});
  doc["textures"] = json::array({{{"source", 0}}});
  doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  doc["meshes"][0]["primitives"][0]["material"] = 0;
  const fs::path file = fs::path(::testing::TempDir()) / "giharness-bad-image.gltf";
  std::ofstream(file) << doc.dump();
  try {
    gi::import_gltf(file);
    FAIL() << "imported an image stb cannot decode";
  } catch (const gi::InputError& e) {
    EXPECT_EQ(e.json_path(), "/images/0");
  }
}

TEST(GltfTextures, ANormalMapWithoutTangentsGetsMikkTSpaceTangents) {
  const gi::Scene s = gi::import_gltf(fs::path(GIHARNESS_SOURCE_DIR) / "scenarios/assets/textured_room.gltf");
  bool found = false;
  for (const gi::Instance& i : s.instances) {
    if (i.name != "back_wall") continue;
    found = true;
    const gi::Mesh& m = s.meshes.at(i.mesh);
    ASSERT_EQ(m.tangents.size(), m.positions.size());
    // The wall's u runs along +x, its v down the wall (−y). A normal map's
    // green is "up" in the image, which is −v in glTF's top-left uv origin,
    // so the bitangent cross(n, t)·w = (+z × +x)·w = +y·w must be +y: w = +1.
    for (const glm::vec4& t : m.tangents) {
      EXPECT_LT(glm::length(glm::vec3(t) - glm::vec3(1, 0, 0)), 1e-5f);
      EXPECT_EQ(t.w, 1.0f);
    }
  }
  EXPECT_TRUE(found);
}

}  // namespace
