#include "core/scene_builder.h"

#include <set>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/scenes/cliff.h"
#include "core/scenes/cornell_box.h"
#include "core/scenes/cache_scenes.h"
#include "core/scenes/di_scenes.h"
#include "core/scenes/gi_scenes.h"

namespace gi {

using nlohmann::json;

namespace {

std::string file_of(const Scenario& s) { return s.file.string(); }

float param_number(const Scenario& s, const json& params, const char* key, double lo, double hi, float fallback) {
  if (!params.contains(key)) return fallback;
  const json& v = params[key];
  const std::string path = std::string("/scene/params/") + key;
  if (!v.is_number() || v.get<double>() < lo || v.get<double>() > hi)
    throw InputError(file_of(s), path, fmt::format("expected a number in [{}, {}], got {}", lo, hi, v.dump()));
  return v.get<float>();
}

// Unknown keys of a generator's params are errors at <base>/<key>.
void only_keys(const Scenario& s, const json& params, const std::string& base, const std::string& generator,
               const std::vector<std::string>& allowed) {
  std::string list;
  for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
  if (!params.is_object()) throw InputError(file_of(s), base, "expected an object, got " + params.dump());
  for (auto it = params.begin(); it != params.end(); ++it)
    if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
      throw InputError(file_of(s), base + "/" + json_pointer_token(it.key()),
                       fmt::format("unknown {} parameter \"{}\"; expected one of: {}", generator, it.key(), list));
}

// The cliff's params (scene generator and mesh generator alike), under `base`.
CliffOptions cliff_options(const Scenario& s, const json& params, const std::string& base) {
  only_keys(s, params, base, "cliff", scenario_keys().cliff_params);
  CliffOptions o;
  auto number = [&](const char* key, double lo, double hi, float fallback) {
    if (!params.contains(key)) return fallback;
    const json& v = params[key];
    if (!v.is_number() || v.get<double>() < lo || v.get<double>() > hi)
      throw InputError(file_of(s), base + "/" + key, fmt::format("expected a number in [{}, {}], got {}", lo, hi, v.dump()));
    return v.get<float>();
  };
  auto integer = [&](const char* key, std::uint64_t lo, std::uint64_t hi, std::uint32_t fallback) {
    if (!params.contains(key)) return fallback;
    const json& v = params[key];
    if (!v.is_number_integer() || v.get<std::int64_t>() < std::int64_t(lo) || v.get<std::uint64_t>() > hi)
      throw InputError(file_of(s), base + "/" + key, fmt::format("expected an integer in {}..{}, got {}", lo, hi, v.dump()));
    return v.get<std::uint32_t>();
  };
  o.triangles = integer("triangles", 12, kCliffMaxTriangles, o.triangles);
  o.seed = integer("seed", 0, 0xffffffffu, o.seed);
  o.width = number("width", 0.01, 1e4, o.width);
  o.height = number("height", 0.01, 1e4, o.height);
  o.depth = number("depth", 0.01, 1e4, o.depth);
  return o;
}

// The generators without parameters, by name: the one list (scene_generators() adds the two with).
const std::vector<std::pair<std::string, Scene (*)()>>& parameterless_generators() {
  static const std::vector<std::pair<std::string, Scene (*)()>> list = {
      {"di_many_lights", &make_di_many_lights},       {"di_occluder", &make_di_occluder},
      {"di_packing_range", &make_di_packing_range},   {"cache_closed_room", &make_cache_closed_room},
      {"cache_room_and_yard", &make_cache_room_and_yard}, {"cache_open_field", &make_cache_open_field},
      {"gi_corners", &make_gi_corners},               {"gi_mirror", &make_gi_mirror},
      {"gi_hard_cases", &make_gi_hard_cases},         {"leak_thin_wall", &make_leak_thin_wall},
      {"leak_zero_thickness_wall", &make_leak_zero_thickness_wall},
      {"gi_indirect_shadow", &make_gi_indirect_shadow}, {"gi_headon_panel", &make_gi_headon_panel},
      {"gi_mirror_shadow_stripe", &make_gi_mirror_shadow_stripe},
      {"di_sun_penumbra", &make_di_sun_penumbra}};
  return list;
}

Scene build_generator(const Scenario& s) {
  const json& params = s.scene.params;
  if (s.scene.generator == "cornell_box") {
    const std::vector<std::string>& allowed = scenario_keys().cornell_box_params;
    std::string list;
    for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
    for (auto it = params.begin(); it != params.end(); ++it)
      if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
        throw InputError(file_of(s), "/scene/params/" + json_pointer_token(it.key()),
                         fmt::format("unknown cornell_box parameter \"{}\"; expected one of: {}", it.key(), list));
    CornellBoxOptions o;
    o.light_scale = param_number(s, params, "light_scale", 0.0, 1e9, o.light_scale);
    o.albedo_scale = param_number(s, params, "albedo_scale", 0.0, 1.37, o.albedo_scale);
    o.scale = param_number(s, params, "scale", 1e-3, 1e3, o.scale);
    if (params.contains("blocks")) {
      if (!params["blocks"].is_boolean())
        throw InputError(file_of(s), "/scene/params/blocks", "expected true or false, got " + params["blocks"].dump());
      o.blocks = params["blocks"].get<bool>();
    }
    return make_cornell_box(o);
  }
  if (s.scene.generator == "cliff") return make_cliff_scene(cliff_options(s, params, "/scene/params"));
  // The DI, cache and GI scenes (core/scenes/di_scenes.h) take no parameters.
  for (const auto& [name, make] : parameterless_generators()) {
    if (s.scene.generator != name) continue;
    if (!params.empty())
      throw InputError(file_of(s), "/scene/params/" + json_pointer_token(params.begin().key()),
                       fmt::format("no parameters: {} takes none", name));
    return make();
  }
  std::string names;
  for (const std::string& n : scene_generators()) names += (names.empty() ? "" : ", ") + n;
  throw InputError(file_of(s), "/scene/generator",
                   fmt::format("expected a scene generator (one of: {}), got \"{}\"", names, s.scene.generator));
}

}  // namespace

const std::vector<std::string>& scene_generators() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = {"cornell_box", "cliff"};
    for (const auto& g : parameterless_generators()) n.push_back(g.first);
    return n;
  }();
  return names;
}

Scene build_scene(const Scenario& s) {
  Scene scene = s.scene.generator.empty() ? import_gltf(s.scene.gltf) : build_generator(s);
  if (s.camera) {
    scene.camera.position = s.camera->position;
    scene.camera.target = s.camera->target;
    if (s.camera->up) scene.camera.up = *s.camera->up;
    if (s.camera->fov_y_degrees) scene.camera.vertical_fov_degrees = *s.camera->fov_y_degrees;
  }
  if (s.background) scene.background = *s.background;
  validate_events(s, scene);
  return scene;
}

GeneratedMesh generate_mesh(const MeshGeneratorSpec& spec, const Scenario& s, const std::string& json_path) {
  if (spec.generator == "cliff")
    return GeneratedMesh{make_cliff_mesh(cliff_options(s, spec.params, json_path + "/mesh/params")),
                         make_cliff_material()};
  throw InputError(file_of(s), json_path + "/mesh/generator",
                   fmt::format("unknown mesh generator \"{}\" (expected one of: cliff)", spec.generator));
}

void validate_events(const Scenario& s, const Scene& initial) {
  std::set<std::string> instances, lights, materials;
  for (const Instance& i : initial.instances) instances.insert(i.name);
  for (const DirectionalLight& l : initial.directional_lights) lights.insert(l.name);
  for (const Material& m : initial.materials) materials.insert(m.name);
  auto fail = [&](const Event& e, const char* key, const std::string& what) {
    throw InputError(file_of(s), e.json_path + "/" + key, what);
  };
  auto need_instance = [&](const Event& e, const char* key, const std::string& n) {
    if (!instances.count(n))
      fail(e, key, fmt::format("expected the name of an instance of the scene or spawned by an earlier event, "
                               "got \"{}\"", n));
  };
  for (std::size_t idx : event_order(s)) {
    const Event& e = s.events[idx];
    switch (e.type) {
      case EventType::LightOn: case EventType::LightOff: case EventType::LightIntensity: case EventType::LightColor:
        if (!instances.count(e.light) && !lights.count(e.light))
          fail(e, "light", fmt::format("expected the name of an emissive instance or a directional light, got \"{}\"",
                                       e.light));
        break;
      case EventType::Spawn:
        if (instances.count(e.instance) || lights.count(e.instance))
          fail(e, "instance", fmt::format("expected a new instance name, \"{}\" already exists", e.instance));
        if (e.mesh) {
          GeneratedMesh g = generate_mesh(*e.mesh, s, e.json_path);
          materials.insert(g.material.name);
        } else {
          need_instance(e, "of", e.of);
        }
        instances.insert(e.instance);
        break;
      case EventType::Despawn:
      case EventType::RemoveRaytracingMesh:
      case EventType::Transform: need_instance(e, "instance", e.instance); break;
      case EventType::Material:
        if (!materials.count(e.material))
          fail(e, "material", fmt::format("expected the name of a material of the scene, got \"{}\"", e.material));
        break;
      case EventType::CameraKeyframes:
      case EventType::CameraSweep: break;
    }
  }
}

}  // namespace gi
