#include "core/scene_events.h"

#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include <glm/gtc/matrix_transform.hpp>

#include "core/errors.h"
#include "core/scene_builder.h"

namespace gi {
namespace {

struct LightState {
  bool on = true;
  float intensity = 1.0f;
  glm::vec3 color{1.0f};
};

// The small part of a scene that events change (meshes are kept aside).
struct State {
  std::vector<Instance> instances;
  std::vector<glm::mat4> base_transform;     // initial (or spawn) transform
  std::vector<glm::vec3> base_emissive_scale;
  std::vector<LightState> instance_lights;
  std::vector<Material> materials;
  std::vector<DirectionalLight> directional;
  std::vector<LightState> directional_lights;
  std::vector<Mesh> generated_meshes;        // appended after initial.meshes
  Camera camera;
  std::unordered_map<std::string, std::uint32_t> instance_index;
};

template <class T>
T lerp_to(const T& a, const T& b, float t) {
  if (t >= 1.0f) return b;  // exact at the end of a range
  return a + (b - a) * t;
}

glm::mat4 delta_transform(const Event& e, float t) {
  const glm::vec3 r = glm::radians(e.rotation_degrees * t);
  glm::mat4 m = glm::translate(glm::mat4(1.0f), e.translation * t);
  m = glm::rotate(m, r.z, glm::vec3(0, 0, 1));
  m = glm::rotate(m, r.y, glm::vec3(0, 1, 0));
  m = glm::rotate(m, r.x, glm::vec3(1, 0, 0));
  return glm::scale(m, lerp_to(glm::vec3(1.0f), e.scale3, t));
}

[[noreturn]] void unknown_name(const Scenario& s, const Event& e, const char* key, const std::string& name) {
  throw InputError(s.file.string(), e.json_path + "/" + key, "expected a known name, got \"" + name + "\"");
}

std::uint32_t instance_of(const State& st, const Scenario& s, const Event& e, const char* key, const std::string& n) {
  auto it = st.instance_index.find(n);
  if (it == st.instance_index.end()) unknown_name(s, e, key, n);
  return it->second;
}

// The light an event names: (is_instance, index).
std::pair<bool, std::uint32_t> light_of(const State& st, const Scenario& s, const Event& e) {
  auto it = st.instance_index.find(e.light);
  if (it != st.instance_index.end()) return {true, it->second};
  for (std::uint32_t i = 0; i < st.directional.size(); ++i)
    if (st.directional[i].name == e.light) return {false, i};
  unknown_name(s, e, "light", e.light);
}

void set_camera_pose(Camera& cam, const glm::vec3& p, const glm::vec3& t, std::optional<float> fov) {
  cam.position = p;
  cam.target = t;
  if (fov) cam.vertical_fov_degrees = *fov;
}

void apply(State& st, const Scene& initial, const Scenario& s, const Event& e, std::uint32_t frame) {
  const float t = event_progress(e, frame);
  switch (e.type) {
    case EventType::LightOn:
    case EventType::LightOff:
    case EventType::LightIntensity:
    case EventType::LightColor: {
      auto [is_instance, i] = light_of(st, s, e);
      LightState& l = is_instance ? st.instance_lights[i] : st.directional_lights[i];
      if (e.type == EventType::LightOn) l.on = true;
      else if (e.type == EventType::LightOff) l.on = false;
      else if (e.type == EventType::LightIntensity) l.intensity = lerp_to(l.intensity, e.scale, t);
      else l.color = lerp_to(l.color, e.color, t);
      break;
    }
    case EventType::CameraKeyframes: {
      const std::vector<CameraKey>& k = e.keys;
      // A key without a field of view carries the previous key's (the first
      // ones: the camera's current one).
      std::vector<float> fov(k.size());
      for (std::size_t i = 0; i < k.size(); ++i)
        fov[i] = k[i].fov_y_degrees.value_or(i ? fov[i - 1] : st.camera.vertical_fov_degrees);
      if (frame <= k.front().frame) {
        set_camera_pose(st.camera, k.front().position, k.front().target, fov.front());
      } else if (frame >= k.back().frame) {
        set_camera_pose(st.camera, k.back().position, k.back().target, fov.back());
      } else {
        std::size_t j = 1;
        while (k[j].frame <= frame) ++j;  // k[j-1].frame <= frame < k[j].frame
        const CameraKey& a = k[j - 1];
        const CameraKey& b = k[j];
        const float u = static_cast<float>(static_cast<double>(frame - a.frame) / static_cast<double>(b.frame - a.frame));
        set_camera_pose(st.camera, lerp_to(a.position, b.position, u), lerp_to(a.target, b.target, u),
                        lerp_to(fov[j - 1], fov[j], u));
      }
      break;
    }
    case EventType::CameraSweep: {
      const float u = e.smooth ? t * t * (3.0f - 2.0f * t) : t;
      const float cur_fov = st.camera.vertical_fov_degrees;
      std::optional<float> fov;
      if (e.from.fov_y_degrees || e.to.fov_y_degrees)
        fov = lerp_to(e.from.fov_y_degrees.value_or(cur_fov), e.to.fov_y_degrees.value_or(cur_fov), u);
      set_camera_pose(st.camera, lerp_to(e.from.position, e.to.position, u), lerp_to(e.from.target, e.to.target, u), fov);
      break;
    }
    case EventType::Spawn: {
      Instance inst;
      glm::vec3 emissive_scale(1.0f);
      const glm::mat4 delta = delta_transform(e, 1.0f);
      if (e.mesh) {
        GeneratedMesh g = generate_mesh(*e.mesh, s, e.json_path);
        inst.mesh = static_cast<std::uint32_t>(initial.meshes.size() + st.generated_meshes.size());
        inst.material = static_cast<std::uint32_t>(st.materials.size());
        inst.transform = delta;
        st.generated_meshes.push_back(std::move(g.mesh));
        st.materials.push_back(std::move(g.material));
      } else {
        const std::uint32_t src = instance_of(st, s, e, "of", e.of);
        inst.mesh = st.instances[src].mesh;
        inst.material = st.instances[src].material;
        inst.transform = delta * st.base_transform[src];
        emissive_scale = st.base_emissive_scale[src];
      }
      inst.name = e.instance;
      inst.emissive_scale = emissive_scale;
      inst.visible = true;
      st.instance_index[inst.name] = static_cast<std::uint32_t>(st.instances.size());
      st.base_transform.push_back(inst.transform);
      st.base_emissive_scale.push_back(emissive_scale);
      st.instance_lights.push_back(LightState{});
      st.instances.push_back(std::move(inst));
      break;
    }
    case EventType::Despawn: st.instances[instance_of(st, s, e, "instance", e.instance)].visible = false; break;
    case EventType::RemoveRaytracingMesh: {
      Instance& inst = st.instances[instance_of(st, s, e, "instance", e.instance)];
      inst.visible = false;
      inst.raytracing_mesh_removed = true;
      break;
    }
    case EventType::Transform: {
      Instance& inst = st.instances[instance_of(st, s, e, "instance", e.instance)];
      inst.transform = delta_transform(e, t) * inst.transform;
      break;
    }
    case EventType::Material: {
      Material* m = nullptr;
      for (Material& x : st.materials)
        if (x.name == e.material) { m = &x; break; }
      if (!m) unknown_name(s, e, "material", e.material);
      if (e.base_color) m->base_color = lerp_to(m->base_color, *e.base_color, t);
      if (e.metallic) m->metallic = lerp_to(m->metallic, *e.metallic, t);
      if (e.perceptual_roughness) m->perceptual_roughness = lerp_to(m->perceptual_roughness, *e.perceptual_roughness, t);
      if (e.reflectance) m->reflectance = lerp_to(m->reflectance, *e.reflectance, t);
      if (e.emissive) m->emissive = lerp_to(m->emissive, *e.emissive, t);
      break;
    }
  }
}

State evaluate_at(const Scene& initial, const Scenario& s, std::uint32_t frame) {
  State st;
  st.instances = initial.instances;
  st.materials = initial.materials;
  st.directional = initial.directional_lights;
  st.camera = initial.camera;
  for (std::uint32_t i = 0; i < st.instances.size(); ++i) {
    st.base_transform.push_back(st.instances[i].transform);
    st.base_emissive_scale.push_back(st.instances[i].emissive_scale);
    st.instance_lights.push_back(LightState{});
    st.instance_index.emplace(st.instances[i].name, i);  // the first of equal names wins
  }
  for (const DirectionalLight& d : st.directional) st.directional_lights.push_back(LightState{true, 1.0f, d.color});

  for (std::size_t idx : event_order(s)) {
    const Event& e = s.events[idx];
    if (e.first > frame) break;  // event_order() sorts by first
    apply(st, initial, s, e, frame);
  }

  for (std::size_t i = 0; i < st.instances.size(); ++i) {
    const LightState& l = st.instance_lights[i];
    st.instances[i].emissive_scale = l.on ? st.base_emissive_scale[i] * l.intensity * l.color : glm::vec3(0.0f);
  }
  for (std::size_t i = 0; i < st.directional.size(); ++i) {
    const LightState& l = st.directional_lights[i];
    st.directional[i].enabled = l.on;
    st.directional[i].illuminance = initial.directional_lights[i].illuminance * l.intensity;
    st.directional[i].color = l.color;
  }
  return st;
}

// The state at `frame` with each instance's previous transform (the one at
// frame − 1) where it moved since.
State evaluate(const Scene& initial, const Scenario& s, std::uint32_t frame) {
  State st = evaluate_at(initial, s, frame);
  if (frame == 0) return st;
  const State before = evaluate_at(initial, s, frame - 1);
  for (std::size_t i = 0; i < st.instances.size() && i < before.instances.size(); ++i)
    if (before.instances[i].transform != st.instances[i].transform)
      st.instances[i].previous_transform = before.instances[i].transform;
  return st;
}

bool same(const Material& a, const Material& b) {
  return a.name == b.name && a.base_color == b.base_color && a.metallic == b.metallic &&
         a.perceptual_roughness == b.perceptual_roughness && a.reflectance == b.reflectance && a.emissive == b.emissive;
}

bool same(const DirectionalLight& a, const DirectionalLight& b) {
  return a.name == b.name && a.direction == b.direction && a.color == b.color && a.illuminance == b.illuminance &&
         a.angular_radius == b.angular_radius && a.enabled == b.enabled;
}

bool same(const Camera& a, const Camera& b) {
  return a.position == b.position && a.target == b.target && a.up == b.up &&
         a.vertical_fov_degrees == b.vertical_fov_degrees;
}

}  // namespace

namespace {

// What differs between `scene` and the evaluated state `st` at a frame.
ChangeSet compare(const Scene& scene, const Scene& initial, const State& st) {
  ChangeSet c;
  // Meshes: the initial ones, then generated ones (deterministic, so a list of
  // the right length is the right list).
  if (scene.meshes.size() != initial.meshes.size() + st.generated_meshes.size()) c.geometry = true;
  if (scene.instances.size() != st.instances.size()) c.geometry = true;
  const std::size_t n = std::min(scene.instances.size(), st.instances.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Instance& a = scene.instances[i];
    const Instance& b = st.instances[i];
    if (a.name != b.name || a.mesh != b.mesh || a.material != b.material) c.geometry = true;
    if (a.transform != b.transform) c.transforms = true;
    if (a.previous_transform != b.previous_transform) c.motion = true;
    if (a.visible != b.visible) c.visibility = true;
    if (a.emissive_scale != b.emissive_scale) c.lights = true;
  }
  if (scene.materials.size() != st.materials.size()) {
    c.materials = c.lights = true;
  } else {
    for (std::size_t i = 0; i < st.materials.size(); ++i) {
      if (!same(scene.materials[i], st.materials[i])) c.materials = true;
      if (scene.materials[i].emissive != st.materials[i].emissive) c.lights = true;
    }
  }
  if (scene.directional_lights.size() != st.directional.size()) {
    c.lights = true;
  } else {
    for (std::size_t i = 0; i < st.directional.size(); ++i)
      if (!same(scene.directional_lights[i], st.directional[i])) c.lights = true;
  }
  if (!same(scene.camera, st.camera)) c.camera = true;
  return c;
}

}  // namespace

ChangeSet apply_events(Scene& scene, const Scene& initial, const Scenario& s, std::uint32_t frame) {
  State st = evaluate(initial, s, frame);
  const ChangeSet c = compare(scene, initial, st);
  const std::size_t mesh_count = initial.meshes.size() + st.generated_meshes.size();
  if (scene.meshes.size() != mesh_count) {
    scene.meshes = initial.meshes;
    for (Mesh& m : st.generated_meshes) scene.meshes.push_back(std::move(m));
  }
  scene.instances = std::move(st.instances);
  scene.materials = std::move(st.materials);
  scene.directional_lights = std::move(st.directional);
  scene.camera = st.camera;
  return c;
}

ChangeSet changes_at(const Scene& scene, const Scene& initial, const Scenario& s, std::uint32_t frame) {
  return compare(scene, initial, evaluate(initial, s, frame));
}

Scene scene_at_frame(const Scene& initial, const Scenario& s, std::uint32_t frame) {
  Scene scene = initial;
  apply_events(scene, initial, s, frame);
  return scene;
}

}  // namespace gi
