// Builds a scenario's initial scene (docs/design.md §7): a built-in generator or a
// glTF file, then the scenario's camera, then validate_events().
#pragma once
#include "core/scenario.h"
#include "core/scene.h"

namespace gi {

// Generators: "cornell_box" (params: light_scale ≥ 0, albedo_scale in
// [0, 1.37] so that no albedo exceeds 1, blocks: bool); "cliff" (params:
// triangles, seed, width, height, depth; core/scenes/cliff.h). Otherwise
// scene.gltf is imported with import_gltf(). Throws InputError: unknown
// generator (/scene/generator), bad params (/scene/params/<key>), glTF errors,
// and whatever validate_events() rejects.
Scene build_scene(const Scenario& scenario);

// Every scene generator's name, as "generator" accepts it (schema.json's
// description lists them; tests/scenario_test.cpp holds it to this list).
const std::vector<std::string>& scene_generators();

// Checks every name the events use against `initial` (the scene build_scene
// returns) in application order (frame, then position in the file): lights
// name an instance (looked up first) or a directional light; instances and
// materials exist in the initial scene or were spawned by an event applied
// earlier; spawned names are new; spawn "of" names an existing instance;
// spawn "mesh" generators exist ("cliff"; others: "unknown mesh generator").
void validate_events(const Scenario& scenario, const Scene& initial);

// A spawned mesh ("spawn" with "mesh": {"generator", "params"}): its mesh and
// material. Generators: "cliff" (the cliff scene's params, material "rock").
// Others: InputError at <json_path>/mesh/generator, "unknown mesh generator".
struct GeneratedMesh {
  Mesh mesh;
  Material material;
};
GeneratedMesh generate_mesh(const MeshGeneratorSpec& spec, const Scenario& scenario, const std::string& json_path);

}  // namespace gi
