// glTF import: the glossy room asset, and hand-written bad files that must be
// InputErrors naming the file and a JSON pointer into the glTF.
#include "core/gltf_import.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "tests/gltf_fixture.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path kGlossyRoom = fs::path(GIHARNESS_SOURCE_DIR) / "scenarios/assets/glossy_room.gltf";

using gi::test::append;
using gi::test::TinyGltf;

class GltfImport : public ::testing::Test {
 protected:
  GltfImport()
      : tmp_(std::string("gltf_") + ::testing::UnitTest::GetInstance()->current_test_info()->name()),
        dir_(tmp_.path()) {}

  fs::path write(const json& doc, const std::string& name = "bad.gltf") {
    const fs::path p = dir_ / name;
    std::ofstream(p) << doc.dump(1);
    return p;
  }

  // Imports `file`, expects an InputError at `path` whose message names the file.
  void expect_error(const fs::path& file, const std::string& path, const std::string& mentions = "") {
    try {
      gi::import_gltf(file);
      ADD_FAILURE() << "no InputError for " << file << " (expected one at " << path << ")";
    } catch (const gi::InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.json_path(), path) << what;
      EXPECT_EQ(e.file(), file.string()) << what;
      EXPECT_NE(what.find(file.string()), std::string::npos) << what;
      EXPECT_NE(what.find(path), std::string::npos) << what;
      if (!mentions.empty()) {
        EXPECT_NE(what.find(mentions), std::string::npos) << what;
      }
    }
  }

  gi::test::TempDir tmp_;  // removed when the test ends
  const fs::path dir_;
};

bool has_warning(const gi::Scene& s, const std::string& text) {
  for (const auto& w : s.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

glm::vec3 centre(const gi::Scene& s, const gi::Instance& inst) {
  const gi::Mesh& m = s.meshes[inst.mesh];
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : m.positions) {
    const glm::vec3 w = glm::vec3(inst.transform * glm::vec4(p, 1.0f));
    lo = glm::min(lo, w);
    hi = glm::max(hi, w);
  }
  return (lo + hi) * 0.5f;
}

#define EXPECT_VEC3_NEAR(a, b, eps)   \
  do {                                \
    const glm::vec3 a_ = (a), b_ = (b); \
    EXPECT_NEAR(a_.x, b_.x, eps);     \
    EXPECT_NEAR(a_.y, b_.y, eps);     \
    EXPECT_NEAR(a_.z, b_.z, eps);     \
  } while (0)

}  // namespace

// ---- the glossy room ---------------------------------------------------------

TEST_F(GltfImport, GlossyRoomCountsAndNames) {
  const gi::Scene s = gi::import_gltf(kGlossyRoom);
  EXPECT_EQ(s.name, "glossy_room");
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  // room (2 primitives), light, two spheres sharing accessors.
  EXPECT_EQ(s.meshes.size(), 5u);
  EXPECT_EQ(s.materials.size(), 5u);
  ASSERT_EQ(s.instances.size(), 5u);
  for (const char* name : {"room/0", "room/1", "ceiling_light", "dielectric_sphere", "metal_sphere"})
    EXPECT_TRUE(s.find_instance(name).has_value()) << name;
  const gi::Mesh& walls = s.meshes[s.instances[*s.find_instance("room/0")].mesh];
  EXPECT_EQ(walls.triangle_count(), 8u);
  EXPECT_EQ(walls.normals.size(), walls.positions.size());
  const gi::Mesh& light = s.meshes[s.instances[*s.find_instance("ceiling_light")].mesh];
  EXPECT_EQ(light.triangle_count(), 2u);  // non-indexed
  const gi::Mesh& sphere = s.meshes[s.instances[*s.find_instance("metal_sphere")].mesh];
  EXPECT_EQ(sphere.positions.size(), 33u * 17u);
  EXPECT_EQ(sphere.triangle_count(), 2u * 32u * 15u);
  for (const glm::vec3& n : sphere.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
  EXPECT_EQ(s.triangle_count(), 8u + 2u + 2u + 2u * 2u * 32u * 15u);
}

TEST_F(GltfImport, GlossyRoomMaterials) {
  const gi::Scene s = gi::import_gltf(kGlossyRoom);
  auto mat = [&](const char* inst) { return s.materials[s.instances[*s.find_instance(inst)].material]; };
  const gi::Material white = mat("room/0"), ceiling = mat("room/1"), emitter = mat("ceiling_light");
  const gi::Material dielectric = mat("dielectric_sphere"), metal = mat("metal_sphere");
  EXPECT_VEC3_NEAR(white.base_color, glm::vec3(0.8f), 1e-6f);
  EXPECT_EQ(white.perceptual_roughness, 1.0f);
  EXPECT_EQ(white.metallic, 0.0f);
  EXPECT_VEC3_NEAR(ceiling.base_color, glm::vec3(0.4f), 1e-6f);
  EXPECT_VEC3_NEAR(emitter.emissive, glm::vec3(10.0f), 1e-5f);  // factor 1 × strength 10
  EXPECT_VEC3_NEAR(white.emissive, glm::vec3(0.0f), 0.0f);
  EXPECT_VEC3_NEAR(dielectric.base_color, glm::vec3(0.8f, 0.3f, 0.2f), 1e-6f);
  EXPECT_EQ(dielectric.metallic, 0.0f);
  EXPECT_NEAR(dielectric.perceptual_roughness, 0.5f, 1e-6f);
  EXPECT_NEAR(dielectric.reflectance, 0.5f, 1e-6f);  // specularFactor 1, ior 1.5 → F0 0.04
  EXPECT_VEC3_NEAR(metal.base_color, glm::vec3(0.95f, 0.8f, 0.5f), 1e-6f);
  EXPECT_EQ(metal.metallic, 1.0f);
  EXPECT_NEAR(metal.perceptual_roughness, 0.3f, 1e-6f);
}

TEST_F(GltfImport, GlossyRoomHierarchyCameraAndSun) {
  const gi::Scene s = gi::import_gltf(kGlossyRoom);
  // props: T(0, 0, −0.4) · R_y(30°); metal_sphere: T(0.9, 0.4, −0.3) · S(0.8).
  const glm::mat4 props = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -0.4f)), glm::radians(30.0f),
                                      glm::vec3(0, 1, 0));
  const glm::vec3 expected = glm::vec3(props * glm::vec4(0.9f, 0.4f, -0.3f, 1.0f));
  const gi::Instance& metal = s.instances[*s.find_instance("metal_sphere")];
  EXPECT_VEC3_NEAR(glm::vec3(metal.transform[3]), expected, 1e-5f);
  EXPECT_VEC3_NEAR(centre(s, metal), expected, 1e-5f);
  EXPECT_NEAR(centre(s, metal).y, 0.4f, 1e-5f);  // resting on the floor (radius 0.5 × 0.8)
  EXPECT_NEAR(glm::length(glm::vec3(metal.transform[0])), 0.8f, 1e-6f);
  const gi::Instance& light = s.instances[*s.find_instance("ceiling_light")];
  EXPECT_VEC3_NEAR(centre(s, light), glm::vec3(0.0f, 2.99f, 0.0f), 1e-6f);

  // Camera: at (0, 1.5, 6.2) looking down −Z, pitched 4° down.
  EXPECT_VEC3_NEAR(s.camera.position, glm::vec3(0.0f, 1.5f, 6.2f), 1e-6f);
  const glm::vec3 fwd = glm::normalize(s.camera.target - s.camera.position);
  const float a = glm::radians(4.0f);
  EXPECT_VEC3_NEAR(fwd, glm::vec3(0.0f, -std::sin(a), -std::cos(a)), 1e-5f);
  EXPECT_NEAR(glm::dot(s.camera.up, fwd), 0.0f, 1e-5f);
  EXPECT_GT(s.camera.up.y, 0.99f);
  EXPECT_NEAR(s.camera.vertical_fov_degrees, 0.7f * 180.0f / 3.14159265f, 1e-4f);

  ASSERT_EQ(s.directional_lights.size(), 1u);
  const gi::DirectionalLight& sun = s.directional_lights[0];
  EXPECT_EQ(sun.name, "sun");
  EXPECT_VEC3_NEAR(sun.direction, glm::normalize(glm::vec3(-0.35f, 0.45f, 1.0f)), 1e-5f);
  EXPECT_NEAR(sun.illuminance, 3.0f, 1e-6f);
  EXPECT_NEAR(sun.angular_radius, 0.02f, 1e-7f);
  EXPECT_VEC3_NEAR(sun.color, glm::vec3(1.0f, 0.96f, 0.9f), 1e-6f);
}

// ---- small valid files -----------------------------------------------------------

TEST_F(GltfImport, MinimalTriangleAndDefaults) {
  json d = TinyGltf{}.doc();
  d["extensions"]["KHR_lights_punctual"]["lights"] = json::array({{{"type", "directional"}, {"intensity", 2.0}},
                                                                  {{"type", "point"}}});
  d["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  d["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  d["scenes"][0]["nodes"] = {0, 1, 2};
  d.erase("scene");
  const gi::Scene s = gi::import_gltf(write(d, "ok.gltf"));
  EXPECT_EQ(s.triangle_count(), 1u);
  ASSERT_EQ(s.instances.size(), 1u);
  EXPECT_EQ(s.instances[0].name, "tri");
  ASSERT_EQ(s.directional_lights.size(), 1u);
  EXPECT_EQ(s.directional_lights[0].name, "node_1");
  EXPECT_VEC3_NEAR(s.directional_lights[0].direction, glm::vec3(0, 0, 1), 0.0f);
  EXPECT_NEAR(s.directional_lights[0].angular_radius, 0.00465f, 1e-7f);
  EXPECT_TRUE(has_warning(s, "no default scene")) << ::testing::PrintToString(s.warnings);
  EXPECT_TRUE(has_warning(s, "point light")) << ::testing::PrintToString(s.warnings);
  EXPECT_TRUE(has_warning(s, "default material")) << ::testing::PrintToString(s.warnings);
  EXPECT_TRUE(has_warning(s, "no perspective camera")) << ::testing::PrintToString(s.warnings);
}

// Textures are imported (tests/texture_test.cpp); occlusion is not: a path
// tracer has no use for it, and its image is never decoded.
// Bevy's loader: reflectance = 0.5 × specularFactor, ior unused for F0
// (v0.19.0:crates/bevy_gltf/src/loader/mod.rs:1483). F0 = 0.04 s², not the
// glTF spec's dielectric F0 × s.
TEST_F(GltfImport, ReflectanceIsHalfTheSpecularFactorAsBevyLoadsIt) {
  auto reflectance = [&](const json& extensions, const std::string& name) {
    json d = TinyGltf{}.doc();
    d["materials"] = json::array({{{"extensions", extensions}}});
    d["meshes"][0]["primitives"][0]["material"] = 0;
    const gi::Scene s = gi::import_gltf(write(d, name));
    return std::make_pair(s.materials.at(0).reflectance, s.warnings);
  };
  EXPECT_NEAR(reflectance({{"KHR_materials_specular", {{"specularFactor", 0.5}}}}, "half.gltf").first, 0.25f, 1e-7f);
  EXPECT_EQ(reflectance({{"KHR_materials_specular", {{"specularFactor", 0.0}}}}, "zero.gltf").first, 0.0f);
  const auto [r, warnings] = reflectance({{"KHR_materials_ior", {{"ior", 1.0}}}}, "ior.gltf");
  EXPECT_NEAR(r, 0.5f, 1e-7f);
  bool warned = false;
  for (const auto& w : warnings) warned = warned || w.find("ior ignored") != std::string::npos;
  EXPECT_TRUE(warned) << ::testing::PrintToString(warnings);
}

TEST_F(GltfImport, OcclusionTexturesAreWarnings) {
  json d = TinyGltf{}.doc();
  d["materials"] = json::array({{{"occlusionTexture", {{"index", 0}}}}});
  d["textures"] = json::array({{{"source", 0}}});
  d["images"] = json::array({{{"uri", "data:image/png;base64,AAAA"}}});
  d["meshes"][0]["primitives"][0]["material"] = 0;
  const gi::Scene s = gi::import_gltf(write(d, "tex.gltf"));
  EXPECT_TRUE(has_warning(s, "occlusionTexture ignored")) << ::testing::PrintToString(s.warnings);
  EXPECT_TRUE(s.images.empty());
}

TEST_F(GltfImport, GlbWithBinChunk) {
  const TinyGltf t;
  json d = t.doc();
  const auto bin = t.bytes();
  d["buffers"][0].erase("uri");
  std::string js = d.dump();
  js.resize((js.size() + 3) & ~std::size_t(3), ' ');
  std::vector<unsigned char> glb;
  auto u32 = [&](std::uint32_t v) { append(glb, std::vector<std::uint32_t>{v}); };
  glb.insert(glb.end(), {'g', 'l', 'T', 'F'});
  u32(2);
  u32(std::uint32_t(12 + 8 + js.size() + 8 + bin.size()));
  u32(std::uint32_t(js.size()));
  u32(0x4E4F534Au);
  glb.insert(glb.end(), js.begin(), js.end());
  u32(std::uint32_t(bin.size()));
  u32(0x004E4942u);
  glb.insert(glb.end(), bin.begin(), bin.end());
  const fs::path p = dir_ / "tri.glb";
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), std::streamsize(glb.size()));
  const gi::Scene s = gi::import_gltf(p);
  EXPECT_EQ(s.triangle_count(), 1u);
  EXPECT_VEC3_NEAR(s.meshes[0].positions[1], glm::vec3(1, 0, 0), 0.0f);

  // A truncated .glb is an error, not a crash.
  const fs::path cut = dir_ / "cut.glb";
  std::ofstream(cut, std::ios::binary).write(reinterpret_cast<const char*>(glb.data()), 30);
  EXPECT_THROW(gi::import_gltf(cut), gi::InputError);
}

TEST_F(GltfImport, ZeroAreaEmitter) {
  // One degenerate triangle beside a real one: stated, kept, never sampled.
  TinyGltf t;
  t.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0};
  t.indices = {0, 1, 2, 0, 1, 3};  // the second is collinear
  json d = t.doc();
  d["bufferViews"][1]["byteOffset"] = 48;
  d["bufferViews"][0]["byteLength"] = 48;
  d["bufferViews"][1]["byteLength"] = 12;
  d["accessors"][0]["count"] = 4;
  d["accessors"][1]["count"] = 6;
  d["materials"] = json::array({{{"emissiveFactor", {1, 1, 1}}}});
  d["meshes"][0]["primitives"][0]["material"] = 0;
  const gi::Scene s = gi::import_gltf(write(d, "partly_flat_light.gltf"));
  EXPECT_EQ(s.meshes[0].triangle_count(), 2u);  // kept
  EXPECT_TRUE(has_warning(s, "zero area")) << ::testing::PrintToString(s.warnings);

  // An emitter whose every triangle is degenerate cannot emit: bad input.
  TinyGltf flat;
  flat.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  d = flat.doc();
  d["materials"] = json::array({{{"emissiveFactor", {1, 1, 1}}}});
  d["meshes"][0]["primitives"][0]["material"] = 0;
  expect_error(write(d, "flat_light.gltf"), "/nodes/0", "zero area");
}

// ---- bad files: InputError with file and JSON path ---------------------------------

TEST_F(GltfImport, IndexOutOfRange) {
  TinyGltf t;
  t.indices = {0, 1, 5};
  expect_error(write(t.doc()), "/meshes/0/primitives/0/indices", "index 2 is 5");
}

TEST_F(GltfImport, MissingBufferFile) {
  json d = TinyGltf{}.doc();
  d["buffers"][0]["uri"] = "missing.bin";
  expect_error(write(d), "/buffers/0/uri", "missing.bin");
}

TEST_F(GltfImport, NaNInAVertex) {
  TinyGltf t;
  t.positions[4] = std::numeric_limits<float>::quiet_NaN();
  expect_error(write(t.doc()), "/accessors/0", "vertex 1");
  t.positions[4] = std::numeric_limits<float>::infinity();
  expect_error(write(t.doc()), "/accessors/0", "vertex 1");
}

TEST_F(GltfImport, NaNInANodeTransform) {
  // JSON has no NaN and nlohmann rejects 1e999; 1e39 is the largest-kind
  // value JSON carries that is not a 32-bit float.
  json d = TinyGltf{}.doc();
  d["nodes"][0]["translation"] = {0.0, 1e39, 0.0};
  expect_error(write(d), "/nodes/0/translation", "32-bit");
  d = TinyGltf{}.doc();
  d["nodes"][0]["rotation"] = {0.0, 0.0, 0.0, 0.0};
  expect_error(write(d), "/nodes/0/rotation", "unit quaternion");
  // Finite locals whose composition overflows.
  d = TinyGltf{}.doc();
  d["nodes"][0]["scale"] = {1e20, 1e20, 1e20};
  d["nodes"].push_back({{"children", {0}}, {"scale", {1e20, 1e20, 1e20}}});
  d["scenes"][0]["nodes"] = {1};
  expect_error(write(d), "/nodes/0", "finite world transform");
}

TEST_F(GltfImport, RecursiveNodes) {
  json d = TinyGltf{}.doc();
  d["nodes"][0]["children"] = {1};
  d["nodes"].push_back({{"children", {0}}});
  expect_error(write(d, "cycle.gltf"), "/nodes/1/children/0", "tree");
  // A node reached twice (two parents) is an error too.
  d = TinyGltf{}.doc();
  d["nodes"].push_back({{"children", {0}}});
  d["scenes"][0]["nodes"] = {0, 1};
  expect_error(write(d, "shared.gltf"), "/nodes/1/children/0", "reached again");
  // A child index out of range.
  d = TinyGltf{}.doc();
  d["nodes"][0]["children"] = {7};
  expect_error(write(d, "dangling.gltf"), "/nodes/0/children/0");
}

TEST_F(GltfImport, EmptyScene) {
  json d = TinyGltf{}.doc();
  d["nodes"][0].erase("mesh");  // (an empty node list is a schema error: tests/gltf_schema_test.cpp)
  expect_error(write(d), "/scenes/0", "at least one triangle");
}

TEST_F(GltfImport, NonTriangleMode) {
  json d = TinyGltf{}.doc();
  d["meshes"][0]["primitives"][0]["mode"] = 1;
  expect_error(write(d), "/meshes/0/primitives/0/mode", "LINES");
}

TEST_F(GltfImport, OutOfBoundsViewsAndAccessors) {
  json d = TinyGltf{}.doc();
  d["bufferViews"][1]["byteLength"] = 4000;
  expect_error(write(d, "view.gltf"), "/bufferViews/1");
  d = TinyGltf{}.doc();
  d["accessors"][0]["count"] = 4;
  expect_error(write(d, "acc.gltf"), "/accessors/0");
  d = TinyGltf{}.doc();
  d["accessors"][0]["byteOffset"] = 40;
  expect_error(write(d, "offset.gltf"), "/accessors/0");
  d = TinyGltf{}.doc();
  d["meshes"][0]["primitives"][0]["indices"] = 9;
  expect_error(write(d, "ref.gltf"), "/meshes/0/primitives/0/indices");
  d = TinyGltf{}.doc();
  d["accessors"][1]["sparse"] = {{"count", 1},
                                 {"indices", {{"bufferView", 1}, {"componentType", 5123}}},
                                 {"values", {{"bufferView", 0}}}};
  expect_error(write(d, "sparse.gltf"), "/accessors/1/sparse");
}

TEST_F(GltfImport, NotAFile) {
  expect_error(dir_ / "nope.gltf", "");
  std::ofstream(dir_ / "junk.gltf") << "{ not json";
  expect_error(dir_ / "junk.gltf", "", "JSON");
}
