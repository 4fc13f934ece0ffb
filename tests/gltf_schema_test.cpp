// Strict glTF 2.0 schema validation (core/gltf_schema.h): one case
// per rule class and object kind, each breaking a valid document that uses
// every object kind in exactly one place and asserting the JSON pointer of
// the InputError. Then the project's own files: every shipped valid glTF
// passes, every committed invalid sample fails where expected.json says.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/gltf_schema.h"
#include "tests/gltf_fixture.h"
#include "tests/test_support.h"

namespace gi {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kSourceDir = GIHARNESS_SOURCE_DIR;
const char* const kValid = "(valid)";

// The one-triangle fixture grown to use every object kind of the core schema
// and every extension the importer reads, each valid. Index layout the cases
// below rely on: accessors 0 POSITION, 1 indices, 2 animation input, 3 sparse;
// bufferViews 0, 1; images 0 (uri), 1 (bufferView); nodes 0 mesh, 1 camera,
// 2 matrix parent of 3, 3 light, 4 skinned; cameras 0 perspective,
// 1 orthographic; lights 0 directional, 1 point, 2 spot.
json full_document() {
  json doc = test::TinyGltf{}.doc();
  doc.merge_patch(json::parse(R"({
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_specular",
                       "KHR_materials_ior", "KHR_texture_transform"],
    "extensionsRequired": ["KHR_lights_punctual"],
    "asset": {"version": "2.0", "generator": "gltf_schema_test", "copyright": "none", "minVersion": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 4]}],
    "nodes": [
      {"name": "tri", "mesh": 0},
      {"camera": 0, "translation": [0, 0, 3], "rotation": [0, 0, 0, 1], "scale": [1, 1, 1]},
      {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], "children": [3]},
      {"extensions": {"KHR_lights_punctual": {"light": 0}}},
      {"mesh": 0, "skin": 0, "weights": [0.5]}
    ],
    "meshes": [{"weights": [0.5], "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0,
                                                   "mode": 4, "targets": [{"POSITION": 0}]}]}],
    "accessors": [
      {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3", "normalized": false,
       "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "SCALAR"},
      {"componentType": 5126, "count": 3, "type": "SCALAR",
       "sparse": {"count": 1, "indices": {"bufferView": 1, "byteOffset": 0, "componentType": 5123},
                  "values": {"bufferView": 0, "byteOffset": 0}}}
    ],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36, "byteStride": 12, "target": 34962},
                    {"buffer": 0, "byteOffset": 36, "byteLength": 6, "target": 34963}],
    "materials": [{
      "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0.5, "roughnessFactor": 0.5,
        "baseColorTexture": {"index": 0, "texCoord": 0, "extensions": {"KHR_texture_transform":
          {"offset": [0, 0], "rotation": 0.5, "scale": [1, 1], "texCoord": 0}}},
        "metallicRoughnessTexture": {"index": 0}},
      "normalTexture": {"index": 0, "scale": 1},
      "occlusionTexture": {"index": 0, "strength": 1},
      "emissiveTexture": {"index": 0},
      "emissiveFactor": [1, 1, 1], "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": true,
      "extensions": {
        "KHR_materials_emissive_strength": {"emissiveStrength": 2},
        "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 1, 1],
                                   "specularTexture": {"index": 0}, "specularColorTexture": {"index": 0}},
        "KHR_materials_ior": {"ior": 1.5}}
    }],
    "textures": [{"sampler": 0, "source": 0}],
    "images": [{"uri": "data:image/png;base64,iVBORw0KGgo="}, {"bufferView": 1, "mimeType": "image/png"}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33071}],
    "cameras": [{"type": "perspective", "perspective": {"aspectRatio": 1.5, "yfov": 0.8, "zfar": 100, "znear": 0.01}},
                {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "zfar": 10, "znear": 0}}],
    "skins": [{"inverseBindMatrices": 2, "skeleton": 0, "joints": [0]}],
    "animations": [{"channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}],
                    "samplers": [{"input": 2, "interpolation": "LINEAR", "output": 0}]}],
    "extensions": {"KHR_lights_punctual": {"lights": [
      {"type": "directional", "color": [1, 0.9, 0.8], "intensity": 3},
      {"type": "point", "intensity": 10, "range": 5},
      {"type": "spot", "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}
    ]}}
  })"));
  return doc;
}

// The JSON pointer of the first violation, or kValid.
std::string first_violation(const json& doc, bool glb = false, const std::string& file = "test.gltf") {
  try {
    validate_gltf_document(doc, file, glb);
    return kValid;
  } catch (const InputError& e) {
    return e.json_path();
  }
}

json with(json doc, const std::string& pointer, json value) {
  doc[json::json_pointer(pointer)] = std::move(value);
  return doc;
}

json without(json doc, const std::string& pointer) {
  const json::json_pointer p(pointer);
  doc[p.parent_pointer()].erase(p.back());
  return doc;
}

// One edit of the full document and where the violation must be reported
// (the edited pointer unless `at` says otherwise).
struct Edit {
  std::string pointer;
  json value;
  std::string at = "";
};

void expect_each_edit_fails(const std::vector<Edit>& edits) {
  for (const Edit& e : edits) {
    const std::string where = e.at.empty() ? e.pointer : e.at;
    EXPECT_EQ(first_violation(with(full_document(), e.pointer, e.value)), where)
        << e.pointer << " = " << e.value.dump();
  }
}

TEST(GltfSchema, FullDocumentAndTinyFixtureAreValid) {
  EXPECT_EQ(first_violation(full_document()), kValid);
  EXPECT_EQ(first_violation(test::TinyGltf{}.doc()), kValid);
}

TEST(GltfSchema, TopLevelMustBeAnObject) {
  EXPECT_EQ(first_violation(json::array()), "");
  EXPECT_EQ(first_violation(json("glTF")), "");
}

// ---- JSON types, one per object kind -----------------------------------------

TEST(GltfSchema, WrongJsonTypeInEachObjectKind) {
  expect_each_edit_fails({
      // root: arrays, the asset object, extension name lists
      {"/accessors", json::object()},
      {"/asset", json::array()},
      {"/extensionsUsed", "KHR_lights_punctual"},
      {"/extensionsUsed/0", 1},
      {"/nodes/0", 5},
      // asset
      {"/asset/version", 2.0},
      {"/asset/generator", 1},
      {"/asset/minVersion", 2},
      // scene
      {"/scenes/0/nodes", 0},
      {"/scenes/0/nodes/0", "0"},
      // node
      {"/nodes/1/translation", "up"},
      {"/nodes/1/translation/0", "0"},
      {"/nodes/1/rotation/3", true},
      {"/nodes/1/scale", 1},
      {"/nodes/2/matrix", json::object()},
      {"/nodes/0/mesh", 0.5},  // an index is an integer, not any number
      {"/nodes/4/weights/0", "0.5"},
      // mesh and primitive
      {"/meshes/0/primitives", json::object()},
      {"/meshes/0/weights/0", true},
      {"/meshes/0/primitives/0", json::array()},
      {"/meshes/0/primitives/0/attributes", json::array({0})},
      {"/meshes/0/primitives/0/mode", "TRIANGLES"},
      {"/meshes/0/primitives/0/targets/0", 0},
      // accessor and sparse
      {"/accessors/0/count", "3"},
      {"/accessors/0/normalized", 0},
      {"/accessors/0/max", 1},
      {"/accessors/0/min/0", "0"},
      {"/accessors/0/type", 3},
      {"/accessors/3/sparse", json::array()},
      {"/accessors/3/sparse/count", 1.5},
      {"/accessors/3/sparse/indices", 1},
      {"/accessors/3/sparse/values/byteOffset", "0"},
      // bufferView and buffer
      {"/bufferViews/0/byteLength", "36"},
      {"/bufferViews/0/byteStride", 12.5},
      {"/buffers/0/uri", 5},
      {"/buffers/0/byteLength", "44"},
      // material, pbrMetallicRoughness, textureInfo kinds
      {"/materials/0/doubleSided", "yes"},
      {"/materials/0/pbrMetallicRoughness", 1},
      {"/materials/0/pbrMetallicRoughness/metallicFactor", "0"},
      {"/materials/0/pbrMetallicRoughness/baseColorTexture", 0},
      {"/materials/0/emissiveFactor", 1},
      {"/materials/0/alphaCutoff", "0.5"},
      {"/materials/0/alphaMode", 1},
      {"/materials/0/normalTexture/scale", "1"},
      {"/materials/0/occlusionTexture/strength", json::array()},
      {"/materials/0/emissiveTexture/texCoord", 0.5},
      {"/materials/0/extensions", json::array()},
      // texture, image, sampler
      {"/textures/0/source", "0"},
      {"/images/0/uri", 7},
      {"/images/1/mimeType", 1},
      {"/samplers/0/wrapS", "REPEAT"},
      // camera
      {"/cameras/0/type", 1},
      {"/cameras/0/perspective", "p"},
      {"/cameras/0/perspective/yfov", "0.8"},
      {"/cameras/1/orthographic/xmag", nullptr},
      // skin
      {"/skins/0/joints", 0},
      // animation, channel, target, sampler
      {"/animations/0/channels", json::object()},
      {"/animations/0/channels/0/target", 0},
      {"/animations/0/channels/0/sampler", "0"},
      {"/animations/0/samplers/0/interpolation", 1},
      // extensions the importer reads
      {"/extensions/KHR_lights_punctual/lights", json::object()},
      {"/extensions/KHR_lights_punctual/lights/0/intensity", "3"},
      {"/extensions/KHR_lights_punctual/lights/2/spot", 0.5},
      {"/nodes/3/extensions/KHR_lights_punctual/light", "0"},
      {"/nodes/3/extensions/KHR_lights_punctual", 0},
      {"/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength", "2"},
      {"/materials/0/extensions/KHR_materials_specular/specularFactor", "0.5"},
      {"/materials/0/extensions/KHR_materials_ior/ior", "1.5"},
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/rotation", "0"},
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset", 0},
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/texCoord", 1.5},
  });
}

// ---- string-typed properties, every one of the schema ---------------------------

// The row's pointer with each "*" as item 0: where full_document() has it.
std::string first_item(const std::string& pattern) {
  std::string out;
  for (std::size_t at = 0; at < pattern.size(); ++at)
    out += pattern.compare(at, 2, "/*") == 0 ? (++at, std::string("/0")) : std::string(1, pattern[at]);
  return out;
}

std::string expected_at(const json& doc, const std::string& pointer) {
  try {
    validate_gltf_document(doc, "test.gltf", false);
    return kValid;
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), pointer) << e.what();
    return e.expected();
  }
}

// Each row of the table (the schema's string-typed properties): a number
// there is "a string" at its pointer, any string passes (the enums: only
// their values, the version pattern: only <major>.<minor>).
TEST(GltfSchema, EveryStringTypedPropertyMustBeAString) {
  const json full = full_document();
  ASSERT_GE(gltf_string_properties().size(), 29u);
  for (const GltfStringProperty& p : gltf_string_properties()) {
    SCOPED_TRACE(p.pointer + " (" + p.schema + ")");
    const std::string at = first_item(p.pointer);
    const json::json_pointer ptr(at);
    ASSERT_TRUE(full.contains(ptr.parent_pointer())) << "full_document() has no " << ptr.parent_pointer().to_string();
    for (const json& wrong : {json(42), json(true), json::array({"x"}), json::object(), json(nullptr)}) {
      const std::string expected = expected_at(with(full, at, wrong), at);
      EXPECT_EQ(expected.rfind("a string", 0), 0u) << wrong.dump() << ": " << expected;
    }
    // A string passes: the one there, else the enum's first value, a version, a name.
    const std::string fine = full.contains(ptr)  ? full[ptr].get<std::string>()
                             : !p.values.empty() ? p.values.front()
                             : !p.pattern.empty() ? "2.0"
                                                  : "any name";
    EXPECT_EQ(first_violation(with(full, at, fine)), kValid) << fine;
    if (!p.values.empty()) {
      const std::string expected = expected_at(with(full, at, "NOT_" + p.values.front()), at);
      EXPECT_EQ(expected.rfind("one of \"" + p.values.front() + "\"", 0), 0u) << expected;
    }
    if (!p.pattern.empty())
      for (const char* bad : {"2", "2.0.1", "02.0", "2.x", " 2.0", "2.1234567890"})
        EXPECT_EQ(first_violation(with(full, at, bad)), at) << bad;
    if (p.required) EXPECT_EQ(first_violation(without(full, at)), ptr.parent_pointer().to_string());
  }
}

// Every object kind the root holds is a glTFChildOfRootProperty, with a name:
// the table has one for each array of full_document() (which uses them all).
TEST(GltfSchema, EveryChildOfTheRootHasItsNameChecked) {
  std::vector<std::string> kinds = {"/extensions/KHR_lights_punctual/lights"};
  const json full = full_document();
  for (const auto& [key, value] : full.items())
    if (value.is_array() && value[0].is_object()) kinds.push_back("/" + key);
  EXPECT_EQ(kinds.size(), 14u);  // the 13 arrays of objects of glTF.schema.json, + lights
  for (const std::string& kind : kinds) {
    const auto& t = gltf_string_properties();
    EXPECT_TRUE(std::any_of(t.begin(), t.end(), [&](const GltfStringProperty& p) { return p.pointer == kind + "/*/name"; }))
        << kind;
    EXPECT_EQ(first_violation(with(full, kind + "/0/name", 42)), kind + "/0/name");
  }
}

TEST(GltfSchema, ASceneNamedByANumberIsNamedInTheMessage) {
  try {
    validate_gltf_document(with(test::TinyGltf{}.doc(), "/scenes/0/name", 42), "scene.gltf", false);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "scene.gltf: /scenes/0/name: a string");
  }
}

// ---- index references, every kind ---------------------------------------------

struct IndexRef {
  std::string pointer;
  std::string collection;  // JSON pointer of the array it indexes
  std::size_t size;        // that array's size in full_document()
};

const std::vector<IndexRef>& index_refs() {
  static const std::vector<IndexRef> refs = {
      {"/scene", "/scenes", 1},
      {"/scenes/0/nodes/0", "/nodes", 5},
      {"/nodes/2/children/0", "/nodes", 5},
      {"/nodes/0/mesh", "/meshes", 1},
      {"/nodes/1/camera", "/cameras", 2},
      {"/nodes/4/skin", "/skins", 1},
      {"/nodes/3/extensions/KHR_lights_punctual/light", "/extensions/KHR_lights_punctual/lights", 3},
      {"/meshes/0/primitives/0/attributes/POSITION", "/accessors", 4},
      {"/meshes/0/primitives/0/indices", "/accessors", 4},
      {"/meshes/0/primitives/0/material", "/materials", 1},
      {"/meshes/0/primitives/0/targets/0/POSITION", "/accessors", 4},
      {"/accessors/0/bufferView", "/bufferViews", 2},
      {"/accessors/3/sparse/indices/bufferView", "/bufferViews", 2},
      {"/accessors/3/sparse/values/bufferView", "/bufferViews", 2},
      {"/bufferViews/0/buffer", "/buffers", 1},
      {"/images/1/bufferView", "/bufferViews", 2},
      {"/textures/0/source", "/images", 2},
      {"/textures/0/sampler", "/samplers", 1},
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/index", "/textures", 1},
      {"/materials/0/pbrMetallicRoughness/metallicRoughnessTexture/index", "/textures", 1},
      {"/materials/0/normalTexture/index", "/textures", 1},
      {"/materials/0/occlusionTexture/index", "/textures", 1},
      {"/materials/0/emissiveTexture/index", "/textures", 1},
      {"/materials/0/extensions/KHR_materials_specular/specularTexture/index", "/textures", 1},
      {"/materials/0/extensions/KHR_materials_specular/specularColorTexture/index", "/textures", 1},
      {"/skins/0/joints/0", "/nodes", 5},
      {"/skins/0/skeleton", "/nodes", 5},
      {"/skins/0/inverseBindMatrices", "/accessors", 4},
      {"/animations/0/samplers/0/input", "/accessors", 4},
      {"/animations/0/samplers/0/output", "/accessors", 4},
      {"/animations/0/channels/0/target/node", "/nodes", 5},
      {"/animations/0/channels/0/sampler", "/animations/0/samplers", 1},
  };
  return refs;
}

void expect_index_rejected(const IndexRef& ref, json value) {
  try {
    validate_gltf_document(with(full_document(), ref.pointer, value), "test.gltf", false);
    ADD_FAILURE() << ref.pointer << " = " << value.dump() << " accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), ref.pointer) << e.what();
    const std::string range = "an index into " + ref.collection + " (0.." + std::to_string(ref.size - 1) + ")";
    EXPECT_EQ(e.expected(), range) << e.what();
  }
}

TEST(GltfSchema, EveryIndexKindJustPastTheEndIsRejected) {
  for (const IndexRef& ref : index_refs()) {
    expect_index_rejected(ref, ref.size);
    // The last valid index passes (unless uniqueness or another rule objects).
    EXPECT_NE(first_violation(with(full_document(), ref.pointer, ref.size - 1)), ref.pointer) << ref.pointer;
  }
}

TEST(GltfSchema, EveryIndexKindNegativeIsRejected) {
  for (const IndexRef& ref : index_refs()) expect_index_rejected(ref, -1);
}

TEST(GltfSchema, IndexIntoAnAbsentArrayIsRejected) {
  try {
    validate_gltf_document(without(full_document(), "/cameras"), "test.gltf", false);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/nodes/1/camera");
    EXPECT_EQ(e.expected(), "an index into /cameras (which has no items)");
  }
}

TEST(GltfSchema, MessageNamesFilePathAndExpectation) {
  try {
    validate_gltf_document(with(full_document(), "/textures/0/source", 2), "scene.gltf", false);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "scene.gltf");
    EXPECT_EQ(std::string(e.what()), "scene.gltf: /textures/0/source: an index into /images (0..1)");
  }
}

// ---- required properties, one per object kind ---------------------------------

TEST(GltfSchema, MissingRequiredPropertyIsReportedAtItsObject) {
  const std::vector<std::pair<std::string, std::string>> removed_and_at = {
      {"/asset", ""},
      {"/asset/version", "/asset"},
      {"/meshes/0/primitives", "/meshes/0"},
      {"/meshes/0/primitives/0/attributes", "/meshes/0/primitives/0"},
      {"/accessors/0/componentType", "/accessors/0"},
      {"/accessors/0/count", "/accessors/0"},
      {"/accessors/0/type", "/accessors/0"},
      {"/accessors/3/sparse/count", "/accessors/3/sparse"},
      {"/accessors/3/sparse/indices", "/accessors/3/sparse"},
      {"/accessors/3/sparse/values", "/accessors/3/sparse"},
      {"/accessors/3/sparse/indices/bufferView", "/accessors/3/sparse/indices"},
      {"/accessors/3/sparse/indices/componentType", "/accessors/3/sparse/indices"},
      {"/accessors/3/sparse/values/bufferView", "/accessors/3/sparse/values"},
      {"/bufferViews/0/buffer", "/bufferViews/0"},
      {"/bufferViews/0/byteLength", "/bufferViews/0"},
      {"/buffers/0/byteLength", "/buffers/0"},
      {"/buffers/0/uri", "/buffers/0"},  // not a GLB: the bytes must come from somewhere
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/index", "/materials/0/pbrMetallicRoughness/baseColorTexture"},
      {"/materials/0/normalTexture/index", "/materials/0/normalTexture"},
      {"/materials/0/occlusionTexture/index", "/materials/0/occlusionTexture"},
      {"/images/0/uri", "/images/0"},  // an image needs a uri or a bufferView
      {"/images/1/mimeType", "/images/1"},  // required with bufferView
      {"/cameras/0/type", "/cameras/0"},
      {"/cameras/0/perspective", "/cameras/0"},  // required by type "perspective"
      {"/cameras/0/perspective/yfov", "/cameras/0/perspective"},
      {"/cameras/0/perspective/znear", "/cameras/0/perspective"},
      {"/cameras/1/orthographic/xmag", "/cameras/1/orthographic"},
      {"/cameras/1/orthographic/ymag", "/cameras/1/orthographic"},
      {"/cameras/1/orthographic/zfar", "/cameras/1/orthographic"},
      {"/cameras/1/orthographic/znear", "/cameras/1/orthographic"},
      {"/skins/0/joints", "/skins/0"},
      {"/animations/0/channels", "/animations/0"},
      {"/animations/0/samplers", "/animations/0"},
      {"/animations/0/channels/0/sampler", "/animations/0/channels/0"},
      {"/animations/0/channels/0/target", "/animations/0/channels/0"},
      {"/animations/0/channels/0/target/path", "/animations/0/channels/0/target"},
      {"/animations/0/samplers/0/input", "/animations/0/samplers/0"},
      {"/animations/0/samplers/0/output", "/animations/0/samplers/0"},
      {"/extensions/KHR_lights_punctual/lights", "/extensions/KHR_lights_punctual"},
      {"/extensions/KHR_lights_punctual/lights/0/type", "/extensions/KHR_lights_punctual/lights/0"},
      {"/extensions/KHR_lights_punctual/lights/2/spot", "/extensions/KHR_lights_punctual/lights/2"},
      {"/nodes/3/extensions/KHR_lights_punctual/light", "/nodes/3/extensions/KHR_lights_punctual"},
  };
  for (const auto& [removed, at] : removed_and_at)
    EXPECT_EQ(first_violation(without(full_document(), removed)), at) << "without " << removed;
}

TEST(GltfSchema, DefaultedPropertiesMayBeLeftOut) {
  // Optional properties with schema defaults: removing them keeps the document valid.
  for (const char* p : {"/accessors/0/byteOffset", "/accessors/0/normalized", "/bufferViews/0/byteStride",
                        "/bufferViews/0/target", "/meshes/0/primitives/0/mode", "/materials/0/alphaMode",
                        "/samplers/0/wrapS", "/cameras/0/perspective/zfar", "/animations/0/samplers/0/interpolation",
                        "/extensions/KHR_lights_punctual/lights/0/intensity", "/scene"})
    EXPECT_EQ(first_violation(without(full_document(), p)), kValid) << "without " << p;
}

// ---- enums --------------------------------------------------------------------

TEST(GltfSchema, ValuesOutsideEachEnum) {
  expect_each_edit_fails({
      {"/accessors/0/componentType", 5124},  // INT: WebGL has it, glTF does not
      {"/accessors/0/type", "VEC5"},
      {"/accessors/0/type", "vec3"},  // enums are case-sensitive
      {"/accessors/3/sparse/indices/componentType", 5126},  // sparse indices are unsigned integers
      {"/meshes/0/primitives/0/mode", 7},
      {"/meshes/0/primitives/0/mode", -1},
      {"/bufferViews/0/target", 34964},
      {"/samplers/0/magFilter", 9984},  // mipmap filters are minification-only
      {"/samplers/0/minFilter", 1},
      {"/samplers/0/wrapS", 0},
      {"/samplers/0/wrapT", 10496},
      {"/images/1/mimeType", "image/gif"},
      {"/materials/0/alphaMode", "opaque"},
      {"/cameras/0/type", "fisheye"},
      {"/animations/0/samplers/0/interpolation", "CUBIC"},
      {"/animations/0/channels/0/target/path", "color"},
      {"/extensions/KHR_lights_punctual/lights/0/type", "area"},
  });
}

// ---- numeric ranges -----------------------------------------------------------

TEST(GltfSchema, NumbersOutsideTheirRanges) {
  expect_each_edit_fails({
      {"/buffers/0/byteLength", 0},                // minimum 1
      {"/bufferViews/0/byteLength", 0},            // minimum 1
      {"/bufferViews/0/byteOffset", -4},           // minimum 0
      {"/bufferViews/0/byteLength", 4294967296},   // 32-bit sizes
      {"/bufferViews/0/byteStride", 2},            // minimum 4
      {"/bufferViews/0/byteStride", 256},          // maximum 252
      {"/bufferViews/0/byteStride", 14},           // multipleOf 4
      {"/accessors/0/count", 0},                   // minimum 1
      {"/accessors/0/byteOffset", -1},             // minimum 0
      {"/accessors/3/sparse/count", 0},            // minimum 1
      {"/accessors/3/sparse/indices/byteOffset", -1},
      {"/materials/0/pbrMetallicRoughness/baseColorFactor/0", 1.5},  // factors in [0, 1]
      {"/materials/0/pbrMetallicRoughness/metallicFactor", 1.1},
      {"/materials/0/pbrMetallicRoughness/roughnessFactor", -0.1},
      {"/materials/0/emissiveFactor/2", -0.1},
      {"/materials/0/occlusionTexture/strength", 2},
      {"/materials/0/alphaCutoff", -1},
      {"/materials/0/emissiveTexture/texCoord", -1},
      {"/cameras/0/perspective/yfov", 0},          // exclusiveMinimum 0
      {"/cameras/0/perspective/znear", 0},         // exclusiveMinimum 0
      {"/cameras/0/perspective/aspectRatio", 0},
      {"/cameras/0/perspective/zfar", 0.001},      // zfar > znear (0.01)
      {"/cameras/1/orthographic/zfar", 0},         // exclusiveMinimum 0
      {"/cameras/1/orthographic/znear", -1},       // minimum 0
      {"/nodes/1/rotation/0", 1.5},                // quaternion components in [-1, 1]
      {"/extensions/KHR_lights_punctual/lights/0/intensity", -1},
      {"/extensions/KHR_lights_punctual/lights/0/color/1", 1.5},
      {"/extensions/KHR_lights_punctual/lights/1/range", 0},
      {"/extensions/KHR_lights_punctual/lights/2/spot/outerConeAngle", 2.0},  // ≤ π/2
      {"/extensions/KHR_lights_punctual/lights/2/spot/innerConeAngle", -0.1},
      {"/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength", -1},
      {"/materials/0/extensions/KHR_materials_specular/specularFactor", 1.5},
      {"/materials/0/extensions/KHR_materials_specular/specularColorFactor/0", -1},
      {"/materials/0/extensions/KHR_materials_ior/ior", 0.5},  // 0 or ≥ 1
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/texCoord", -1},
      {"/asset/version", "1.0"},  // glTF 2.x only
      {"/asset/version", "2"},    // "<major>.<minor>"
  });
  // Spot cone: inner < outer.
  EXPECT_EQ(first_violation(with(full_document(), "/extensions/KHR_lights_punctual/lights/2/spot/innerConeAngle", 0.6)),
            "/extensions/KHR_lights_punctual/lights/2/spot");
  // ior = 0 is the schema's special value.
  EXPECT_EQ(first_violation(with(full_document(), "/materials/0/extensions/KHR_materials_ior/ior", 0)), kValid);
}

TEST(GltfSchema, ArrayLengths) {
  expect_each_edit_fails({
      {"/materials/0/pbrMetallicRoughness/baseColorFactor", {1, 1, 1}},  // 4 items
      {"/materials/0/emissiveFactor", {1, 1, 1, 1}},                     // 3 items
      {"/nodes/2/matrix", std::vector<int>(15, 0)},                      // 16 items
      {"/nodes/1/rotation", {0, 0, 1}},                                  // 4 items
      {"/nodes/1/translation", {0, 0, 0, 0}},                            // 3 items
      {"/nodes/1/scale", {1, 1}},                                        // 3 items
      {"/nodes/4/weights", json::array()},                               // minItems 1
      {"/nodes/2/children", json::array()},
      {"/meshes/0/weights", json::array()},
      {"/meshes/0/primitives", json::array()},
      {"/meshes/0/primitives/0/targets", json::array()},
      {"/meshes/0/primitives/0/attributes", json::object(), ""},
      {"/accessors/0/max", json::array()},                               // 1..16 items
      {"/accessors/0/min", std::vector<int>(17, 0)},
      {"/scenes/0/nodes", json::array()},
      {"/skins/0/joints", json::array()},
      {"/animations/0/channels", json::array()},
      {"/animations/0/samplers", json::array()},
      {"/materials", json::array()},  // every top-level array: minItems 1
      {"/extensionsUsed", json::array()},
      {"/extensions/KHR_lights_punctual/lights/0/color", {1, 1}},
      {"/extensions/KHR_lights_punctual/lights", json::array()},
      {"/materials/0/extensions/KHR_materials_specular/specularColorFactor", {1, 1}},
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset", {0, 0, 0}},
      {"/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/scale", {1}},
  });
}

// ---- uniqueness, dependencies, exclusions --------------------------------------

TEST(GltfSchema, UniqueItemsDependenciesAndExclusions) {
  expect_each_edit_fails({
      {"/scenes/0/nodes/1", 0, "/scenes/0/nodes/1"},  // uniqueItems
      {"/skins/0/joints", {0, 0}, "/skins/0/joints/1"},
      {"/extensionsUsed/1", "KHR_lights_punctual", "/extensionsUsed/1"},
      {"/nodes/1/matrix", std::vector<int>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, "/nodes/1/matrix"},
      {"/cameras/0/orthographic", {{"xmag", 1}, {"ymag", 1}, {"zfar", 10}, {"znear", 0}}, "/cameras/0/orthographic"},
      {"/images/1/uri", "data:image/png;base64,iVBORw0KGgo=", "/images/1/bufferView"},  // uri or bufferView
      {"/accessors/3/byteOffset", 0, "/accessors/3"},  // byteOffset needs a bufferView
  });
  EXPECT_EQ(first_violation(without(full_document(), "/nodes/4/mesh")), "/nodes/4");  // skin and weights need a mesh
  EXPECT_EQ(first_violation(without(full_document(), "/scenes")), "/scene");          // nothing to index
}

TEST(GltfSchema, UnknownPropertiesExtrasAndOtherExtensionsAreAllowed) {
  json d = full_document();
  d["extras"] = {{"anything", json::array({1, "two"})}};
  d["nodes"][0]["futureProperty"] = "x";
  d["materials"][0]["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", "not checked"}};
  EXPECT_EQ(first_violation(d), kValid);
}

// ---- where buffers come from ----------------------------------------------------

TEST(GltfSchema, OnlyTheFirstBufferOfAGlbMayOmitItsUri) {
  json d = without(full_document(), "/buffers/0/uri");
  EXPECT_EQ(first_violation(d, /*glb=*/true), kValid);
  EXPECT_EQ(first_violation(d, /*glb=*/false), "/buffers/0");
  d["buffers"].push_back({{"byteLength", 4}});
  EXPECT_EQ(first_violation(d, /*glb=*/true), "/buffers/1");
}

TEST(GltfSchema, RelativeBufferUrisMustNameAnExistingFile) {
  const fs::path dir = fs::temp_directory_path() / ("gltf_schema_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "data file.bin") << "0123456789012345678901234567890123456789abcd";
  const std::string file = (dir / "scene.gltf").string();
  json d = with(full_document(), "/buffers/0/uri", "data%20file.bin");  // URI-encoded
  EXPECT_EQ(first_violation(d, false, file), kValid);
  d = with(full_document(), "/buffers/0/uri", "missing.bin");
  EXPECT_EQ(first_violation(d, false, file), "/buffers/0/uri");
  fs::remove_all(dir);
}

// ---- the project's files -----------------------------------------------------------

json read_json_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return json::parse(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
}

std::vector<fs::path> gltf_files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".gltf") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// The committed invalid samples: file name → JSON pointer of their violation.
std::map<std::string, std::string> invalid_samples() {
  std::map<std::string, std::string> out;
  const json expected = read_json_file(kSourceDir / "tests/data/gltf/invalid/expected.json");
  for (const auto& [name, path] : expected.items())
    out[name] = path.get<std::string>();
  return out;
}

// Shipped files that are not schema-valid on purpose (fuzz seeds), and why.
const std::map<std::string, std::string> kInvalidOnPurpose = {
    {"hostile_duplicate_key.gltf", "asset.version given twice; the last, \"1.0\", is no glTF 2"},
    {"hostile_huge_accessor_count.gltf", "a .gltf buffer without uri"},
    {"hostile_huge_number.gltf", "1e400 overflows a double: not parseable JSON for the importer"},
    {"hostile_deep_extras.gltf", "valid, but nested deeper than the importer's JSON reader allows"},
};

TEST(GltfSchema, EveryShippedValidGltfPasses) {
  const auto invalid = invalid_samples();
  std::size_t checked = 0;
  for (const char* dir : {"scenarios/assets", "tests/fuzz/corpus/gltf"}) {
    for (const fs::path& p : gltf_files_in(kSourceDir / dir)) {
      const std::string name = p.filename().string();
      if (kInvalidOnPurpose.count(name) || invalid.count(name)) continue;
      SCOPED_TRACE(p.string());
      EXPECT_NO_THROW(validate_gltf_document(read_json_file(p), p.string(), false));
      ++checked;
    }
  }
  EXPECT_GE(checked, 7u) << "glossy_room (twice), camera_and_lights, emissive_metal, hierarchy, recursive_nodes, triangle";
}

// The samples and their fuzz corpus copies fail where expected.json says
// (validator alone: what import_gltf must report once it calls it first).
TEST(GltfSchema, CommittedInvalidSamplesFailAtTheirRecordedPath) {
  const auto samples = invalid_samples();
  ASSERT_GE(samples.size(), 8u);
  for (const auto& [name, path] : samples) {
    for (const char* dir : {"tests/data/gltf/invalid", "tests/fuzz/corpus/gltf"}) {
      const fs::path p = kSourceDir / dir / name;
      SCOPED_TRACE(p.string());
      ASSERT_TRUE(fs::is_regular_file(p));
      EXPECT_EQ(first_violation(read_json_file(p), false, p.string()), path);
    }
  }
}

TEST(GltfSchemaImport, CommittedInvalidSamplesAreRejectedAtTheirRecordedPath) {
  for (const auto& [name, path] : invalid_samples()) {
    const fs::path p = kSourceDir / "tests/data/gltf/invalid" / name;
    try {
      (void)import_gltf(p);
      ADD_FAILURE() << p << " imported; expected an InputError at " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.json_path(), path) << e.what();
    }
  }
}

// scenes[0].name = 42, through the importer and the command line: an
// InputError, exit 2, naming the file and /scenes/0/name.
TEST(GltfSchemaImport, ASceneNameThatIsANumberIsExitTwo) {
  test::TempDir dir("gltf_scene_name");
  const fs::path gltf = dir.path() / "named.gltf";
  std::ofstream(gltf) << with(test::TinyGltf{}.doc(), "/scenes/0/name", 42).dump(1);
  try {
    (void)import_gltf(gltf);
    ADD_FAILURE() << "imported";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/scenes/0/name") << e.what();
    EXPECT_EQ(e.expected(), "a string") << e.what();
  }
  const fs::path scenario = dir.path() / "scenario.json";
  std::ofstream(scenario) << json{{"name", "named"}, {"scene", {{"gltf", gltf.string()}}}, {"resolution", {8, 8}},
                                  {"frames", 1}, {"mode", "reference"}}
                                 .dump();
  const test::CommandResult r = test::run_giharness("run " + scenario.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("named.gltf: /scenes/0/name: a string"), std::string::npos) << r.output;
}

// What a user sees: `giharness run` on a scenario of each sample is exit 2,
// and the message names the glTF file and the JSON path.
TEST(GltfSchemaImport, EachInvalidSampleIsExitTwoNamingItsPath) {
  test::TempDir dir("gltf_invalid_cli");
  for (const auto& [name, path] : invalid_samples()) {
    const fs::path gltf = kSourceDir / "tests/data/gltf/invalid" / name;
    const fs::path scenario = dir.path() / (name + ".json");
    std::ofstream(scenario) << json{{"name", "invalid"}, {"scene", {{"gltf", gltf.string()}}}, {"resolution", {8, 8}},
                                    {"frames", 1}, {"mode", "reference"}}
                                   .dump();
    const test::CommandResult r = test::run_giharness("run " + scenario.string() + " --out " + (dir.path() / name).string());
    EXPECT_EQ(r.exit_code, 2) << name << ": " << r.output;
    EXPECT_NE(r.output.find(name + ": " + path + ":"), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace gi
