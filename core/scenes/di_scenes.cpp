#include "core/scenes/di_scenes.h"

#include <cmath>

#include "core/scenes/mesh_builder.h"

namespace gi {
namespace {

// Horizontal quad at height y facing down (an emitter) or up (a floor).
Mesh horizontal(const std::string& name, float x0, float x1, float z0, float z1, float y, bool facing_down) {
  Mesh m{name};
  add_quad(m, {x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}, {0.5f * (x0 + x1), y + (facing_down ? -1.0f : 1.0f),
                                                                   0.5f * (z0 + z1)});
  return m;
}

glm::vec3 hue(float h) {
  const glm::vec3 k(0.0f, 2.0f / 3.0f, 1.0f / 3.0f);
  return glm::clamp(glm::abs(glm::fract(glm::vec3(h) + k) * 6.0f - 3.0f) - 1.0f, 0.0f, 1.0f);
}

void add_floor(Scene& s, float half) {
  add_object(s, horizontal("floor", -half, half, -half, half, 0.0f, false), lambert_material("floor", glm::vec3(0.7f)));
}

}  // namespace

Scene make_di_many_lights() {
  Scene s;
  s.name = "di_many_lights";
  add_floor(s, 4.0f);
  add_object(s, box_mesh("box_a", {-1.2f, 0.0f, -0.6f}, {-0.4f, 0.8f, 0.2f}), lambert_material("box_a", glm::vec3(0.6f, 0.6f, 0.55f)));
  add_object(s, box_mesh("box_b", {0.5f, 0.0f, 0.3f}, {1.1f, 0.5f, 0.9f}), lambert_material("box_b", glm::vec3(0.5f, 0.55f, 0.6f)));
  // 32 × 16 small quads at 2 m, facing down, colours around the hue circle
  // and brightness varying over a decade.
  int n = 0;
  for (int i = 0; i < 32; ++i)
    for (int j = 0; j < 16; ++j, ++n) {
      const float x = -3.1f + 0.2f * float(i), z = -1.5f + 0.2f * float(j);
      const float bright = 2.0f + 18.0f * float((n * 37) % 11) / 10.0f;
      const std::string name = "light_" + std::to_string(n);
      add_object(s, horizontal(name, x, x + 0.08f, z, z + 0.08f, 2.0f, true),
                 emitter_material(name, bright * (0.15f + 0.85f * hue(float((n * 7) % 64) / 64.0f))));
    }
  s.camera.position = {0.0f, 2.6f, 4.2f};
  s.camera.target = {0.0f, 0.2f, 0.0f};
  s.camera.vertical_fov_degrees = 50.0f;
  return s;
}

Scene make_di_occluder() {
  Scene s;
  s.name = "di_occluder";
  add_floor(s, 3.0f);
  add_object(s, box_mesh("occluder", {-0.3f, 0.6f, -0.3f}, {0.3f, 0.7f, 0.3f}), lambert_material("occluder", glm::vec3(0.5f)));
  add_object(s, horizontal("light", -0.5f, 0.5f, -0.5f, 0.5f, 1.6f, true), emitter_material("light", glm::vec3(8.0f, 7.0f, 6.0f)));
  s.camera.position = {0.0f, 2.2f, 3.0f};
  s.camera.target = {0.0f, 0.3f, 0.0f};
  s.camera.vertical_fov_degrees = 45.0f;
  return s;
}

// A big sun (5.7° radius: a hazy sky's glow, twenty times the real sun's) over
// a 1.5 m wall: the shadow on the floor has penumbrae up to 0.4 m wide, so
// sampling only the sun's centre (Solari 0.17's hard sun) is a visible error.
Scene make_di_sun_penumbra() {
  Scene s;
  s.name = "di_sun_penumbra";
  add_floor(s, 3.0f);
  add_object(s, box_mesh("wall", {-1.0f, 0.0f, -0.6f}, {1.0f, 1.5f, -0.45f}), lambert_material("wall", glm::vec3(0.6f)));
  DirectionalLight sun;
  sun.name = "sun";
  sun.direction = glm::normalize(glm::vec3(0.35f, 1.0f, -0.9f));
  sun.color = glm::vec3(1.0f, 0.96f, 0.9f);
  sun.illuminance = 3.0f;
  sun.angular_radius = 0.1f;
  s.directional_lights.push_back(sun);
  s.camera.position = {0.0f, 3.2f, 2.6f};
  s.camera.target = {0.0f, 0.0f, 0.4f};
  s.camera.vertical_fov_degrees = 50.0f;
  return s;
}

Scene make_di_packing_range() {
  Scene s;
  s.name = "di_packing_range";
  add_floor(s, 3.0f);
  add_object(s, box_mesh("block", {-0.2f, 0.0f, -0.2f}, {0.2f, 0.4f, 0.2f}), lambert_material("block", glm::vec3(0.6f)));
  add_object(s, horizontal("bright", 0.79f, 0.81f, -0.01f, 0.01f, 1.2f, true), emitter_material("bright", glm::vec3(3e5f, 2.5e5f, 2e5f)));
  add_object(s, horizontal("dim", -1.6f, -0.6f, -0.5f, 0.5f, 1.5f, true), emitter_material("dim", glm::vec3(1.0f)));
  s.camera.position = {0.0f, 2.4f, 3.2f};
  s.camera.target = {0.0f, 0.2f, 0.0f};
  s.camera.vertical_fov_degrees = 50.0f;
  return s;
}

}  // namespace gi
