// glTF 2.0 import (.gltf with embedded or external buffers, and .glb) into the
// scene model (docs/design.md §1, §3 "Materials and lights", §7).
//
// What is imported:
//  - the default scene's node hierarchy (TRS or matrix, parent → child);
//  - TRIANGLES primitives (indexed with u8/u16/u32 indices, or not), float
//    positions, normals when present: one gi::Mesh per (mesh, primitive),
//    shared by every node that uses it; one gi::Instance per (node,
//    primitive), named "<node name or node_N>" plus "/<k>" when the mesh has
//    several primitives;
//  - metallic-roughness factors: base_color (rgb of baseColorFactor),
//    metallic, perceptual_roughness, emissive = emissiveFactor ×
//    KHR_materials_emissive_strength; reflectance = 0.5 × KHR_materials_specular's
//    specularFactor, as Bevy's loader has it (F0 = 0.16 reflectance²; ior
//    not used);
//    a primitive without a material gets the glTF default material;
//  - the first perspective camera reached (depth first, children in order):
//    Scene::camera looks down the node's −Z with the node's +Y up;
//  - KHR_lights_punctual "directional" lights: direction = the node's +Z in
//    world space (towards the light), intensity → illuminance (lux as
//    irradiance), colour, angular radius from the light's
//    "extras": {"angular_radius": radians}, else 0.00465 (the sun). The light
//    is named after its node (else the light's name, else node_N).
//
// Anything not modelled is either a gi::InputError naming the file, a JSON
// pointer into the glTF (e.g. /meshes/2/primitives/0/indices) and what was
// expected, or a sentence in Scene::warnings (textures, point/spot lights,
// skins, morph targets, animations, alpha, ...). Never a silently different
// scene. Malformed files (bad indices, out-of-bounds accessors, NaN/inf data,
// node cycles) are errors, never out-of-bounds reads.
#pragma once
#include <filesystem>

#include "core/scene.h"

namespace gi {

// Throws gi::InputError on anything it cannot import faithfully.
Scene import_gltf(const std::filesystem::path& file);

}  // namespace gi
