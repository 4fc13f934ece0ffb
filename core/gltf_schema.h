// Strict glTF 2.0 schema validation of a parsed glTF JSON document
// ("strict validation"). TinyGLTF is lenient: it accepts wrong JSON types,
// negative or out-of-range indices, unknown enum values and out-of-range
// factors. This is the one place that checks the document against the glTF 2.0
// core schema (https://github.com/KhronosGroup/glTF/tree/main/specification/2.0/schema)
// and the extensions the importer reads (KHR_lights_punctual,
// KHR_materials_emissive_strength, KHR_materials_specular, KHR_materials_ior,
// KHR_texture_transform), before any of the document is used.
//
// Rule classes: JSON types, required properties, enums, numeric ranges and
// array lengths, and every index reference (in range, non-negative). Unknown
// properties, extras and other extensions are allowed, as the schema allows
// them. Besides the schema, it checks what the importer's own limits and the
// spec's prose require (32-bit sizes, asset version 2.x, zfar > znear, a
// buffer without uri only as a GLB's first buffer, an existing buffer file).
//
// String-typed properties are one table (gltf_string_properties): every
// property the schema files type "string" (each object's "name" from
// glTFChildOfRootProperty, asset's four, uri, mimeType, the extension name
// lists' items, and the enums spelled as strings), checked before the rest.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

// One string-typed property of the glTF 2.0 schema (or of an extension the
// importer reads), where it sits in a document.
struct GltfStringProperty {
  std::string pointer;              // JSON pointer; "*" stands for each item of an array: "/scenes/*/name"
  bool required = false;            // the schema's "required" (reported at the enclosing object)
  std::vector<std::string> values;  // the schema's enum (its "const"s); empty: any string
  std::string pattern;              // the schema's "pattern" (ECMAScript), empty: none
  std::string schema;               // the schema file that types it, e.g. "glTFChildOfRootProperty.schema.json"
};

// Every string-typed property, in the order they are checked.
const std::vector<GltfStringProperty>& gltf_string_properties();

// Throws gi::InputError(file, json_pointer, expected) at the first violation,
// e.g. ("/textures/0/source", "an index into /images (0..2)"). `document` is
// the top-level JSON value; `glb` says whether a GLB binary chunk exists (only
// then may buffer 0 omit its uri). Relative buffer URIs resolve against
// `file`'s folder.
void validate_gltf_document(const nlohmann::json& document, const std::string& file, bool glb);

}  // namespace gi
