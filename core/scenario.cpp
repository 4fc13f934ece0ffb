#include "core/scenario.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "core/check_catalog.h"
#include "core/json_input.h"
#include "core/errors.h"
#include "core/json_reader.h"

namespace gi {

using nlohmann::json;

const char* to_string(EventType type) {
  switch (type) {
    case EventType::LightOn: return "light_on";
    case EventType::LightOff: return "light_off";
    case EventType::LightIntensity: return "light_intensity";
    case EventType::LightColor: return "light_color";
    case EventType::CameraKeyframes: return "camera_keyframes";
    case EventType::CameraSweep: return "camera_sweep";
    case EventType::Spawn: return "spawn";
    case EventType::Despawn: return "despawn";
    case EventType::RemoveRaytracingMesh: return "remove_raytracing_mesh";
    case EventType::Transform: return "transform";
    case EventType::Material: return "material";
  }
  return "?";
}

std::string json_pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

const ScenarioKeys& scenario_keys() {
  static const ScenarioKeys keys = [] {
    ScenarioKeys k;
    k.top_level = {"$schema", "name", "description", "scene", "resolution", "frames", "seed", "profile",
                   "overrides", "mode", "gi", "noise", "cache_view", "background", "samples_per_frame", "camera", "events", "checks", "capture", "timeout_seconds", "bug", "pipeline"};
    k.required_top_level = {"name", "scene", "resolution", "frames"};
    k.scene_keys = {"generator", "params", "gltf", "shapes"};
    k.pipelines = {"solari", "radiance_cascades"};
    k.camera_keys = {"position", "target", "up", "fov_y_degrees"};
    k.modes = {"reference", "realtime"};
    k.profiles = {"solari-0.17", "solari-0.18", "solari-0.19", "radiance-cascades-lesson"};
    k.event_types = {"light_on", "light_off", "light_intensity", "light_color", "camera_keyframes",
                     "camera_sweep", "spawn", "despawn", "remove_raytracing_mesh", "transform", "material"};
    k.event_keys = {
        {"light_on", {"type", "frame", "light"}},
        {"light_off", {"type", "frame", "light"}},
        {"light_intensity", {"type", "frame", "frames", "light", "scale"}},
        {"light_color", {"type", "frame", "frames", "light", "color"}},
        {"camera_keyframes", {"type", "keys"}},
        {"camera_sweep", {"type", "frames", "from", "to", "ease"}},
        {"spawn", {"type", "frame", "instance", "of", "mesh", "translation", "rotation_degrees", "scale", "repeat"}},
        {"despawn", {"type", "frame", "instance"}},
        {"remove_raytracing_mesh", {"type", "frame", "instance"}},
        {"transform", {"type", "frame", "frames", "instance", "translation", "rotation_degrees", "scale"}},
        {"material",
         {"type", "frame", "frames", "material", "base_color", "metallic", "perceptual_roughness", "reflectance",
          "emissive"}},
    };
    k.camera_key_keys = {"frame", "position", "target", "fov_y_degrees"};
    k.camera_pose_keys = {"position", "target", "fov_y_degrees"};
    k.mesh_generator_keys = {"generator", "params"};
    k.spawn_repeat_keys = {"count", "frame_step", "first_number", "columns", "first_cell", "step", "row_step"};
    // The checks declare themselves (core/check_catalog.h), each with its keys.
    for (const CheckDeclaration& d : declared_checks()) {
      k.check_names.push_back(d.name);
      k.check_keys[d.name] = d.keys;
    }
    k.cornell_box_params = {"light_scale", "albedo_scale", "blocks", "scale"};
    k.cliff_params = {"triangles", "seed", "width", "height", "depth"};
    return k;
  }();
  return keys;
}

bool Scenario::has_check(const std::string& n) const { return find_check(n) != nullptr; }

const CheckSpec* Scenario::find_check(const std::string& n) const {
  for (const CheckSpec& c : checks)
    if (c.name == n) return &c;
  return nullptr;
}

std::vector<std::size_t> event_order(const Scenario& s) {
  std::vector<std::size_t> order(s.events.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return s.events[a].first < s.events[b].first; });
  return order;
}

namespace {

using Reader = JsonReader;

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// Ranges shared with the schema.
constexpr double kMaxCoordinate = 1e6;    // metres
constexpr double kMaxDegrees = 36000.0;   // rotations (ranged spins may turn many times)
constexpr double kMinScale = 1e-6, kMaxScale = 1e6;
constexpr double kMaxIntensity = 1e9;     // light scales and emission
constexpr double kMaxColor = 1e6;

const std::string kNamePattern = "[a-z0-9_-]+";

bool valid_name(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-')) return false;
  return true;
}

float fov(const Reader& r, const json& j, const std::string& path) { return r.number(j, path, 1.0, 179.0); }

CameraPose parse_pose(const Reader& r, const json& j, const std::string& path) {
  r.object(j, path, scenario_keys().camera_pose_keys, {"position", "target"});
  CameraPose p;
  p.position = r.vec3(j["position"], path + "/position", -kMaxCoordinate, kMaxCoordinate);
  p.target = r.vec3(j["target"], path + "/target", -kMaxCoordinate, kMaxCoordinate);
  if (p.position == p.target) r.fail(path + "/target", "expected a target different from the position");
  if (j.contains("fov_y_degrees")) p.fov_y_degrees = fov(r, j["fov_y_degrees"], path + "/fov_y_degrees");
  return p;
}

glm::vec3 parse_scale(const Reader& r, const json& j, const std::string& path) {
  if (j.is_number()) return glm::vec3(r.number(j, path, kMinScale, kMaxScale));
  if (j.is_array()) return r.vec3(j, path, kMinScale, kMaxScale);
  r.fail(path, fmt::format("expected a number in [{}, {}] or an array of 3 such numbers, {}", kMinScale, kMaxScale, got(j)));
}

// A spawn with "repeat" as the plain spawns it stands for (SpawnRepeat).
std::vector<Event> expand_spawn_repeat(const Event& e) {
  const SpawnRepeat& rep = *e.repeat;
  const std::size_t hash_begin = e.instance.find('#');
  std::size_t hash_end = hash_begin;
  while (hash_end < e.instance.size() && e.instance[hash_end] == '#') ++hash_end;
  const int width = int(hash_end - hash_begin);
  const std::uint32_t columns = rep.columns ? rep.columns : 0xffffffffu;
  std::vector<Event> out;
  out.reserve(rep.count);
  for (std::uint32_t i = 0; i < rep.count; ++i) {
    Event one = e;
    one.repeat.reset();
    one.first = one.last = e.first + i * rep.frame_step;
    one.instance = e.instance.substr(0, hash_begin) + fmt::format("{:0{}}", rep.first_number + i, width) +
                   e.instance.substr(hash_end);
    const std::uint64_t k = std::uint64_t(rep.first_cell) + i;
    one.translation = e.translation + float(k % columns) * rep.step + float(k / columns) * rep.row_step;
    out.push_back(std::move(one));
  }
  return out;
}

Event parse_event(const Reader& r, const json& j, std::size_t index) {
  const ScenarioKeys& K = scenario_keys();
  const std::string path = Reader::at("/events", index);
  if (!j.is_object()) r.fail(path, "expected an event object, " + got(j));
  if (!j.contains("type")) r.fail(path + "/type", fmt::format("missing required key \"type\" (one of {})", join(K.event_types)));
  const std::string type = r.one_of(j["type"], path + "/type", K.event_types);
  const std::vector<std::string>& allowed = K.event_keys.at(type);

  Event e;
  e.type = static_cast<EventType>(std::find(K.event_types.begin(), K.event_types.end(), type) - K.event_types.begin());
  e.index = index;
  e.json_path = path;

  // The event's own required keys (the frame keys are handled below).
  std::vector<std::string> required;
  switch (e.type) {
    case EventType::LightOn: case EventType::LightOff: required = {"light"}; break;
    case EventType::LightIntensity: required = {"light", "scale"}; break;
    case EventType::LightColor: required = {"light", "color"}; break;
    case EventType::CameraKeyframes: required = {"keys"}; break;
    case EventType::CameraSweep: required = {"frames", "from", "to"}; break;
    case EventType::Spawn: case EventType::Despawn: case EventType::RemoveRaytracingMesh: case EventType::Transform:
      required = {"instance"};
      break;
    case EventType::Material: required = {"material"}; break;
  }
  r.object(j, path, allowed, required);

  // When: "frame" or "frames": [first, last].
  const bool may_frame = contains(allowed, "frame"), may_frames = contains(allowed, "frames");
  if (may_frame || may_frames) {
    if (j.contains("frame") && j.contains("frames"))
      r.fail(path + "/frames", "expected either \"frame\" or \"frames\", not both");
    if (j.contains("frames")) {
      const std::string fp = path + "/frames";
      const json& f = j["frames"];
      if (!f.is_array() || f.size() != 2) r.fail(fp, "expected [first, last] (2 frame numbers), " + got(f));
      e.first = r.uint(f[0], fp + "/0", 0, kMaxFrames - 1);
      e.last = r.uint(f[1], fp + "/1", 0, kMaxFrames - 1);
      if (e.last < e.first) r.fail(fp + "/1", fmt::format("expected last >= first ({}), got {}", e.first, e.last));
      e.ranged = true;
    } else if (j.contains("frame")) {
      e.first = e.last = r.uint(j["frame"], path + "/frame", 0, kMaxFrames - 1);
    } else {
      r.fail(path + "/frame", may_frames ? "missing required key \"frame\" (or \"frames\": [first, last])"
                                         : "missing required key \"frame\"");
    }
  }

  auto name = [&](const char* key) { return r.string(j[key], path + "/" + key); };
  switch (e.type) {
    case EventType::LightOn:
    case EventType::LightOff: e.light = name("light"); break;
    case EventType::LightIntensity:
      e.light = name("light");
      e.scale = r.number(j["scale"], path + "/scale", 0.0, kMaxIntensity);
      break;
    case EventType::LightColor:
      e.light = name("light");
      e.color = r.vec3(j["color"], path + "/color", 0.0, kMaxColor);
      break;
    case EventType::CameraKeyframes: {
      const json& keys = r.array(j["keys"], path + "/keys", 1);
      for (std::size_t i = 0; i < keys.size(); ++i) {
        const std::string kp = Reader::at(path + "/keys", i);
        r.object(keys[i], kp, K.camera_key_keys, {"frame", "position", "target"});
        CameraKey k;
        k.frame = r.uint(keys[i]["frame"], kp + "/frame", 0, kMaxFrames - 1);
        if (!e.keys.empty() && k.frame <= e.keys.back().frame)
          r.fail(kp + "/frame", fmt::format("expected key frames in increasing order (> {}), got {}", e.keys.back().frame, k.frame));
        CameraPose p = parse_pose(r, json{{"position", keys[i]["position"]}, {"target", keys[i]["target"]}}, kp);
        k.position = p.position;
        k.target = p.target;
        if (keys[i].contains("fov_y_degrees")) k.fov_y_degrees = fov(r, keys[i]["fov_y_degrees"], kp + "/fov_y_degrees");
        e.keys.push_back(k);
      }
      e.first = 0;  // held before the first key: it governs the camera from frame 0
      e.last = e.keys.back().frame;
      e.ranged = true;
      break;
    }
    case EventType::CameraSweep:
      e.from = parse_pose(r, j["from"], path + "/from");
      e.to = parse_pose(r, j["to"], path + "/to");
      if (j.contains("ease")) e.smooth = r.one_of(j["ease"], path + "/ease", {"linear", "smooth"}) == "smooth";
      break;
    case EventType::Spawn:
      e.instance = name("instance");
      if (j.contains("of") == j.contains("mesh"))
        r.fail(path + "/of", "expected exactly one of \"of\" (an existing instance) or \"mesh\" (a generator)");
      if (j.contains("mesh")) {
        const std::string mp = path + "/mesh";
        r.object(j["mesh"], mp, K.mesh_generator_keys, {"generator"});
        MeshGeneratorSpec m;
        m.generator = r.string(j["mesh"]["generator"], mp + "/generator");
        if (j["mesh"].contains("params")) {
          if (!j["mesh"]["params"].is_object()) r.fail(mp + "/params", "expected an object, " + got(j["mesh"]["params"]));
          m.params = j["mesh"]["params"];
        }
        e.mesh = std::move(m);
      } else {
        e.of = name("of");
      }
      [[fallthrough]];
    case EventType::Transform:
      if (e.type == EventType::Transform) e.instance = name("instance");
      if (j.contains("translation")) e.translation = r.vec3(j["translation"], path + "/translation", -kMaxCoordinate, kMaxCoordinate);
      if (j.contains("rotation_degrees")) e.rotation_degrees = r.vec3(j["rotation_degrees"], path + "/rotation_degrees", -kMaxDegrees, kMaxDegrees);
      if (j.contains("scale")) e.scale3 = parse_scale(r, j["scale"], path + "/scale");
      if (j.contains("repeat")) {
        const std::string rp = path + "/repeat";
        r.object(j["repeat"], rp, K.spawn_repeat_keys, {"count"});
        const json& rj = j["repeat"];
        SpawnRepeat rep;
        rep.count = r.uint(rj["count"], rp + "/count", 1, kMaxSpawnRepeat);
        if (rj.contains("frame_step")) rep.frame_step = r.uint(rj["frame_step"], rp + "/frame_step", 0, kMaxFrames);
        if (rj.contains("first_number")) rep.first_number = r.uint(rj["first_number"], rp + "/first_number", 0, 1u << 30);
        if (rj.contains("columns")) rep.columns = r.uint(rj["columns"], rp + "/columns", 1, kMaxSpawnRepeat);
        if (rj.contains("first_cell")) rep.first_cell = r.uint(rj["first_cell"], rp + "/first_cell", 0, 1u << 30);
        if (rj.contains("step")) rep.step = r.vec3(rj["step"], rp + "/step", -kMaxCoordinate, kMaxCoordinate);
        if (rj.contains("row_step")) rep.row_step = r.vec3(rj["row_step"], rp + "/row_step", -kMaxCoordinate, kMaxCoordinate);
        if (std::uint64_t(e.first) + std::uint64_t(rep.frame_step) * (rep.count - 1) >= kMaxFrames)
          r.fail(rp + "/frame_step", fmt::format("the last spawn's frame must stay below {}", kMaxFrames));
        if (e.instance.find('#') == std::string::npos)
          r.fail(path + "/instance", "a repeated spawn's name needs a run of '#' for its number, e.g. \"cliff_####\"");
        e.repeat = rep;
      }
      break;
    case EventType::Despawn: case EventType::RemoveRaytracingMesh: e.instance = name("instance"); break;
    case EventType::Material:
      e.material = name("material");
      if (j.contains("base_color")) e.base_color = r.vec3(j["base_color"], path + "/base_color", 0.0, 1.0);
      if (j.contains("metallic")) e.metallic = r.number(j["metallic"], path + "/metallic", 0.0, 1.0);
      if (j.contains("perceptual_roughness"))
        e.perceptual_roughness = r.number(j["perceptual_roughness"], path + "/perceptual_roughness", 0.0, 1.0);
      if (j.contains("reflectance")) e.reflectance = r.number(j["reflectance"], path + "/reflectance", 0.0, 1.0);
      if (j.contains("emissive")) e.emissive = r.vec3(j["emissive"], path + "/emissive", 0.0, kMaxIntensity);
      if (!e.base_color && !e.metallic && !e.perceptual_roughness && !e.reflectance && !e.emissive)
        r.fail(path, "expected at least one of base_color, metallic, perceptual_roughness, reflectance, emissive");
      break;
  }
  return e;
}

CheckSpec parse_check(const Reader& r, const json& j, std::size_t index) {
  const ScenarioKeys& K = scenario_keys();
  const std::string path = Reader::at("/checks", index);
  if (!j.is_object()) r.fail(path, "expected a check object {\"name\": …}, " + got(j));
  if (!j.contains("name")) r.fail(path + "/name", fmt::format("missing required key \"name\" (one of {})", join(K.check_names)));
  CheckSpec c;
  c.name = r.one_of(j["name"], path + "/name", K.check_names);
  c.json_path = path;
  r.object(j, path, K.check_keys.at(c.name), {"name"});
  c.params = j;
  c.params.erase("name");
  return c;
}

}  // namespace

Scenario parse_scenario(const json& doc, const std::filesystem::path& file) {
  const ScenarioKeys& K = scenario_keys();
  const Reader r(file.string());
  r.object(doc, "", K.top_level, K.required_top_level);

  Scenario s;
  s.file = file;
  s.raw = doc;

  if (doc.contains("$schema")) r.string(doc["$schema"], "/$schema");
  s.name = r.string(doc["name"], "/name");
  if (!valid_name(s.name)) r.fail("/name", fmt::format("expected a name matching {}, got \"{}\"", kNamePattern, s.name));
  if (doc.contains("description")) s.description = r.string(doc["description"], "/description", false);

  if (doc.contains("pipeline") && r.one_of(doc["pipeline"], "/pipeline", K.pipelines) == "radiance_cascades") {
    s.pipeline = Pipeline::RadianceCascades;
    s.profile = "radiance-cascades-lesson";
  }
  const bool rc = s.pipeline == Pipeline::RadianceCascades;

  // scene
  if (rc) {
    const json& sc = doc["scene"];
    r.object(sc, "/scene", {"shapes"}, {"shapes"});
  } else {
    const json& sc = doc["scene"];
    r.object(sc, "/scene", K.scene_keys);
    if (sc.contains("shapes")) r.fail("/scene/shapes", "unexpected \"shapes\" (a canvas of shapes is the scene of \"pipeline\": \"radiance_cascades\")");
    if (sc.contains("generator") == sc.contains("gltf"))
      r.fail("/scene", "expected exactly one of \"generator\" (with optional \"params\") or \"gltf\"");
    if (sc.contains("generator")) {
      s.scene.generator = r.string(sc["generator"], "/scene/generator");
      if (sc.contains("params")) {
        if (!sc["params"].is_object()) r.fail("/scene/params", "expected an object, " + got(sc["params"]));
        s.scene.params = sc["params"];
      }
    } else {
      if (sc.contains("params")) r.fail("/scene/params", "unexpected \"params\" with \"gltf\" (only generators take params)");
      const std::string g = r.string(sc["gltf"], "/scene/gltf");
      std::filesystem::path p(g);
      if (p.is_relative()) p = file.parent_path() / p;
      std::error_code ec;
      if (!std::filesystem::is_regular_file(p, ec))
        r.fail("/scene/gltf", fmt::format("expected an existing glTF file (relative to the scenario's folder), "
                                          "\"{}\" not found", p.string()));
      s.scene.gltf = p.lexically_normal();
    }
  }

  // resolution, frames, seed
  {
    const json& res = doc["resolution"];
    if (!res.is_array() || res.size() != 2)
      r.fail("/resolution", fmt::format("expected [width, height], integers in 1..{}, {}", kMaxResolution, got(res)));
    s.resolution[0] = r.uint(res[0], "/resolution/0", 1, kMaxResolution);
    s.resolution[1] = r.uint(res[1], "/resolution/1", 1, kMaxResolution);
  }
  s.frames = r.uint(doc["frames"], "/frames", 1, kMaxFrames);
  if (doc.contains("seed")) s.seed = r.uint(doc["seed"], "/seed", 0, 0xffffffffu);
  if (doc.contains("profile")) {
    s.profile = r.one_of(doc["profile"], "/profile", K.profiles);
    if (rc != (s.profile == "radiance-cascades-lesson"))
      r.fail("/profile", rc ? "expected radiance-cascades-lesson (the profile of the radiance_cascades pipeline)"
                            : "expected a Solari profile (radiance-cascades-lesson needs \"pipeline\": \"radiance_cascades\")");
  }
  if (rc) {
    for (const char* key : {"mode", "gi", "noise", "cache_view", "background", "samples_per_frame", "camera"})
      if (doc.contains(key))
        r.fail(std::string("/") + key, "unexpected key for the radiance_cascades pipeline (it belongs to Solari's)");
    s.canvas = parse_canvas(r, doc["scene"]["shapes"], "/scene/shapes", s.resolution[0], s.resolution[1]);
  }
  if (doc.contains("overrides")) {
    if (!doc["overrides"].is_object()) r.fail("/overrides", "expected an object of profile keys, " + got(doc["overrides"]));
    s.overrides = doc["overrides"];
  }
  if (doc.contains("mode"))
    s.mode = r.one_of(doc["mode"], "/mode", K.modes) == "reference" ? RenderMode::Reference : RenderMode::Realtime;
  if (doc.contains("gi")) s.gi = r.boolean(doc["gi"], "/gi");
  if (doc.contains("noise")) s.noise = r.boolean(doc["noise"], "/noise");
  if (doc.contains("cache_view")) s.cache_view = r.boolean(doc["cache_view"], "/cache_view");
  if (doc.contains("background")) s.background = r.vec3(doc["background"], "/background", 0.0, 1e6);
  if (doc.contains("timeout_seconds"))
    s.timeout_seconds = r.uint(doc["timeout_seconds"], "/timeout_seconds", 1, kMaxTimeoutSeconds);
  if (doc.contains("samples_per_frame"))
    s.samples_per_frame = r.uint(doc["samples_per_frame"], "/samples_per_frame", 1, kMaxSamplesPerFrame);

  if (doc.contains("camera")) {
    const json& c = doc["camera"];
    r.object(c, "/camera", K.camera_keys, {"position", "target"});
    CameraSpec cam;
    CameraPose p = parse_pose(r, json{{"position", c["position"]}, {"target", c["target"]}}, "/camera");
    cam.position = p.position;
    cam.target = p.target;
    if (c.contains("up")) {
      glm::vec3 up = r.vec3(c["up"], "/camera/up", -1e6, 1e6);
      if (glm::dot(up, up) == 0.0f) r.fail("/camera/up", "expected a non-zero up vector");
      cam.up = up;
    }
    if (c.contains("fov_y_degrees")) cam.fov_y_degrees = fov(r, c["fov_y_degrees"], "/camera/fov_y_degrees");
    s.camera = cam;
  }

  if (doc.contains("events")) {
    const json& ev = r.array(doc["events"], "/events");
    for (std::size_t i = 0; i < ev.size(); ++i) {
      Event e = parse_event(r, ev[i], i);
      if (!e.repeat) {
        s.events.push_back(std::move(e));
        continue;
      }
      for (Event& one : expand_spawn_repeat(e)) s.events.push_back(std::move(one));
    }
  }
  if (doc.contains("checks")) {
    const json& ch = r.array(doc["checks"], "/checks");
    for (std::size_t i = 0; i < ch.size(); ++i) {
      CheckSpec c = parse_check(r, ch[i], i);
      if (s.has_check(c.name)) r.fail(c.json_path + "/name", fmt::format("expected each check once, \"{}\" repeats", c.name));
      s.checks.push_back(std::move(c));
    }
  }
  if (doc.contains("capture")) {
    const json& cap = r.array(doc["capture"], "/capture");
    for (std::size_t i = 0; i < cap.size(); ++i) {
      const std::string path = Reader::at("/capture", i);
      std::uint32_t f = r.uint(cap[i], path, 0, kMaxFrames - 1);
      // The scenario's own frames bound its captures: a frame the run never
      // reaches is the file's mistake (a --frames run shortened below it is
      // the command line's, replay/run_setup.cpp).
      if (f >= s.frames)
        r.fail(path, fmt::format("expected a frame below \"frames\" ({}), got {}", s.frames, f));
      if (std::find(s.capture.begin(), s.capture.end(), f) != s.capture.end())
        r.fail(path, fmt::format("expected distinct frames, {} repeats", f));
      s.capture.push_back(f);
    }
  }
  if (doc.contains("bug")) {
    const json& b = doc["bug"];
    r.object(b, "/bug", {"source", "symptom", "caught_by"}, {"source", "caught_by"});
    BugSpec bug;
    bug.source = r.string(b["source"], "/bug/source");
    if (b.contains("symptom")) bug.symptom = r.string(b["symptom"], "/bug/symptom", false);
    const json& by = r.array(b["caught_by"], "/bug/caught_by", 1);
    for (std::size_t i = 0; i < by.size(); ++i) {
      const std::string path = Reader::at("/bug/caught_by", i);
      std::string name = r.string(by[i], path);
      if (!s.has_check(name)) r.fail(path, fmt::format("expected the name of one of the scenario's checks, got \"{}\"", name));
      bug.caught_by.push_back(std::move(name));
    }
    s.bug = std::move(bug);
  }
  // The radiance-cascades pipeline has checks of its own (rc_*), and only those.
  for (const CheckSpec& c : s.checks)
    if (rc != (c.name.rfind("rc_", 0) == 0))
      r.fail(c.json_path + "/name", rc ? fmt::format("expected an rc_* check for the radiance_cascades pipeline, got \"{}\"", c.name)
                                       : fmt::format("expected a check of Solari's pipeline (\"{}\" judges \"pipeline\": \"radiance_cascades\")", c.name));
  if (rc) validate_canvas_events(r, s, *s.canvas);
  // Each check's own parameter rules, once the whole scenario is known.
  for (const CheckSpec& c : s.checks)
    if (const CheckDeclaration* d = find_declared_check(c.name); d && d->validate) d->validate(c, s);
  return s;
}

float event_progress(const Event& e, std::uint32_t frame) {
  if (!e.ranged || frame >= e.last || e.last == e.first) return 1.0f;
  return static_cast<float>(static_cast<double>(frame - e.first) / static_cast<double>(e.last - e.first));
}

Scenario load_scenario(const std::filesystem::path& file) {
  return parse_scenario(read_json_input(file, "a readable scenario file"), file);
}

}  // namespace gi
