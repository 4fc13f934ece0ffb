// Scenario files (docs/design.md §7): parsing and validation of the JSON format that
// scenarios/schema.json describes. Every error is a gi::InputError naming the
// file, the JSON Pointer of the offending value and what was expected (exit
// code 2). The parser is the authority; tests/scenario_test.cpp keeps the
// schema's key tables and enums identical to scenario_keys().
//
// Frames are numbered from 0; a scenario of `frames` N renders 0..N-1.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/rc/canvas.h"

namespace gi {

enum class RenderMode { Reference, Realtime };

// Which pipeline a scenario drives: Solari's (3D scenes, the default) or the
// seed lesson's 2D radiance cascades (a canvas of shapes, its own
// passes, profile, CPU reference and rc_* checks).
enum class Pipeline { Solari, RadianceCascades };

enum class EventType {
  LightOn, LightOff, LightIntensity, LightColor,
  CameraKeyframes, CameraSweep,
  Spawn, Despawn, RemoveRaytracingMesh, Transform, Material,
};
const char* to_string(EventType type);  // the JSON spelling ("light_on", …)

struct SceneSpec {
  std::string generator;                       // "cornell_box", …; empty for a glTF scene
  nlohmann::json params = nlohmann::json::object();  // generator parameters (checked by build_scene)
  std::filesystem::path gltf;                  // resolved against the scenario's folder; empty for a generator
};

struct CameraSpec {
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f};
  std::optional<glm::vec3> up;          // absent: keep the scene's
  std::optional<float> fov_y_degrees;   // absent: keep the scene's
};

struct CameraKey {
  std::uint32_t frame = 0;
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f};
  std::optional<float> fov_y_degrees;  // absent: the previous key's (first keys: the camera's)
};

struct CameraPose {
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f};
  std::optional<float> fov_y_degrees;
};

struct MeshGeneratorSpec {
  std::string generator;
  nlohmann::json params = nlohmann::json::object();
};

// spawn "repeat": one event in the file stands for `count` spawns, the i-th
// at frame + i·frame_step, named by the instance's run of '#' replaced with
// first_number + i (zero-padded to the run's length), translated by
// col·step + row·row_step with cell k = first_cell + i, col = k mod columns,
// row = k div columns. The parser expands it into plain spawn events.
struct SpawnRepeat {
  std::uint32_t count = 1;
  std::uint32_t frame_step = 1;
  std::uint32_t first_number = 1;
  std::uint32_t columns = 0;  // 0: one row
  std::uint32_t first_cell = 0;
  glm::vec3 step{0.0f};
  glm::vec3 row_step{0.0f};
};

struct Event {
  EventType type = EventType::LightOn;
  std::size_t index = 0;     // position in the file's "events" array
  std::string json_path;     // "/events/<index>"
  bool ranged = false;       // "frames": [first, last] rather than "frame"
  std::uint32_t first = 0;   // the frame it starts at (camera_keyframes: 0, it holds its first key before it)
  std::uint32_t last = 0;    // == first unless ranged (camera_keyframes: its last key)

  // light_on, light_off, light_intensity, light_color
  std::string light;
  float scale = 1.0f;                 // light_intensity
  glm::vec3 color{1.0f};              // light_color
  // camera_keyframes (sorted by frame, strictly increasing)
  std::vector<CameraKey> keys;
  // camera_sweep
  CameraPose from, to;
  bool smooth = false;                // "ease": "smooth" (smoothstep) rather than "linear"
  // spawn, despawn, remove_raytracing_mesh, transform
  std::string instance;
  std::string of;                     // spawn: copy of this instance (else `mesh`)
  std::optional<MeshGeneratorSpec> mesh;
  glm::vec3 translation{0.0f};
  glm::vec3 rotation_degrees{0.0f};   // xyz Euler: R = Rz·Ry·Rx
  glm::vec3 scale3{1.0f};             // "scale": s or [sx, sy, sz]
  std::optional<SpawnRepeat> repeat;  // spawn, as written (expanded events carry none)
  // material
  std::string material;
  std::optional<glm::vec3> base_color;
  std::optional<float> metallic;
  std::optional<float> perceptual_roughness;
  std::optional<float> reflectance;
  std::optional<glm::vec3> emissive;
};

struct CheckSpec {
  std::string name;                              // one of scenario_keys().check_names
  nlohmann::json params = nlohmann::json::object();  // every key but "name"
  std::string json_path;                         // "/checks/<index>"
};

struct BugSpec {
  std::string source;                  // where the bug and its fix are recorded, e.g. "bevy#21904"
  std::string symptom;                 // what users saw
  std::vector<std::string> caught_by;  // checks of the scenario that must fail
};

struct Scenario {
  std::filesystem::path file;   // where it was read from (errors name it)
  nlohmann::json raw;           // the document as read, every key kept
  std::string name;
  std::string description;
  SceneSpec scene;
  std::array<std::uint32_t, 2> resolution{0, 0};  // width, height
  std::uint32_t frames = 0;
  std::uint32_t seed = 1;
  std::string profile = "solari-0.18";  // radiance_cascades: "radiance-cascades-lesson"
  Pipeline pipeline = Pipeline::Solari;
  // The radiance-cascades pipeline's scene ("scene": {"shapes": [...]}).
  std::optional<Canvas> canvas;
  nlohmann::json overrides = nlohmann::json::object();  // validated later against the profile
  RenderMode mode = RenderMode::Realtime;
  // Realtime: add ReSTIR GI and specular GI to DI (the output and the reference
  // check become full GI). Off by default: DI alone.
  bool gi = false;
  // Realtime: run two independent chains so summary.json reports each
  // signal's per-frame noise (replay/run_scenario.cpp). A reference check
  // runs two chains anyway; otherwise it doubles the DI/GI passes' cost and
  // the second chain's cache queries touch the world cache, so it is opt-in.
  bool noise = false;
  // Realtime, debug: the world cache's view (a cache query at every primary
  // surface each frame, Bevy's VISUALIZE_WORLD_CACHE). Its queries keep cells
  // alive, so it changes the cache it shows; captures gain a "cache_view" layer.
  bool cache_view = false;
  // Radiance shown where a camera ray hits nothing (Bevy's ClearColor): the
  // background only, never a light. Absent: the scene's (black).
  std::optional<glm::vec3> background;
  std::uint32_t samples_per_frame = 1;
  // The nightly's wall-time limit for this scenario's process, in seconds
  // (unset: the suite's --scenario-timeout).
  std::optional<std::uint32_t> timeout_seconds;
  // A scenario that re-creates a known bug (the bug museum, scenarios/bugs/):
  // the nightly reports it caught when every check in caught_by fails, missed
  // otherwise (a failure), and the suite's catch rate.
  std::optional<BugSpec> bug;
  std::optional<CameraSpec> camera;
  std::vector<Event> events;    // in file order
  std::vector<CheckSpec> checks;
  std::vector<std::uint32_t> capture;

  bool has_check(const std::string& check_name) const;
  const CheckSpec* find_check(const std::string& check_name) const;
};

// Reads, parses and validates a scenario file (not the scene: see build_scene).
Scenario load_scenario(const std::filesystem::path& file);
// Same from an already parsed document; `file` names it in errors and is the
// base of relative paths (glTF scenes).
Scenario parse_scenario(const nlohmann::json& doc, const std::filesystem::path& file);

// How far a ranged event has come at `frame`: 1 for a "frame" event and
// once f >= last, else (f − first) / (last − first) (core/scene_events.h).
float event_progress(const Event& e, std::uint32_t frame);

// The order events are applied in: by start frame (Event::first), then by
// position in the file. Indices into scenario.events.
std::vector<std::size_t> event_order(const Scenario& scenario);

// The parser's key tables, the single source the schema is tested against.
struct ScenarioKeys {
  std::vector<std::string> top_level;           // every allowed top-level key
  std::vector<std::string> required_top_level;
  std::vector<std::string> scene_keys;          // "generator", "params", "gltf", "shapes"
  std::vector<std::string> pipelines;           // "solari", "radiance_cascades"
  std::vector<std::string> camera_keys;
  std::vector<std::string> modes;
  std::vector<std::string> profiles;
  std::vector<std::string> event_types;
  std::map<std::string, std::vector<std::string>> event_keys;  // per event type, "type" included
  std::vector<std::string> camera_key_keys;     // camera_keyframes "keys" items
  std::vector<std::string> camera_pose_keys;    // camera_sweep "from"/"to"
  std::vector<std::string> mesh_generator_keys; // spawn "mesh"
  std::vector<std::string> spawn_repeat_keys;   // spawn "repeat"
  std::vector<std::string> check_names;
  // Params of each check with a fixed parameter set ("name" included); checks
  // not listed here accept any parameters (their code validates them).
  std::map<std::string, std::vector<std::string>> check_keys;
  std::vector<std::string> cornell_box_params;
  std::vector<std::string> cliff_params;        // scene generator "cliff" and spawn mesh generator "cliff"
};
const ScenarioKeys& scenario_keys();

// Limits shared by the parser and the schema.
inline constexpr std::uint32_t kMaxResolution = 8192;
inline constexpr std::uint32_t kMaxFrames = 10'000'000;
inline constexpr std::uint32_t kMaxSamplesPerFrame = 1024;
inline constexpr std::uint32_t kMaxTimeoutSeconds = 604800;  // a week
inline constexpr std::uint32_t kMaxSpawnRepeat = 100'000;

// JSON Pointer escaping of one reference token ("~" → "~0", "/" → "~1").
std::string json_pointer_token(const std::string& key);

}  // namespace gi
