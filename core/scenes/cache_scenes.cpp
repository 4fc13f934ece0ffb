#include "core/scenes/cache_scenes.h"

#include "core/scenes/mesh_builder.h"

namespace gi {
namespace {

// The room: x, z in [−2, 2], y in [0, 3]; walls face inwards. With a doorway,
// the +z wall has a 1.2 × 2.2 m opening at x in [−0.6, 0.6].
Mesh room_shell(bool doorway) {
  Mesh m{"room"};
  const glm::vec3 inside(0.0f, 1.5f, 0.0f);
  add_quad(m, {-2, 0, -2}, {2, 0, -2}, {2, 0, 2}, {-2, 0, 2}, inside);    // floor
  add_quad(m, {-2, 3, -2}, {2, 3, -2}, {2, 3, 2}, {-2, 3, 2}, inside);    // ceiling
  add_quad(m, {-2, 0, -2}, {2, 0, -2}, {2, 3, -2}, {-2, 3, -2}, inside);  // back (−z)
  add_quad(m, {-2, 0, -2}, {-2, 3, -2}, {-2, 3, 2}, {-2, 0, 2}, inside);  // left (−x)
  add_quad(m, {2, 0, -2}, {2, 3, -2}, {2, 3, 2}, {2, 0, 2}, inside);      // right (+x)
  if (!doorway) {
    add_quad(m, {-2, 0, 2}, {2, 0, 2}, {2, 3, 2}, {-2, 3, 2}, inside);    // front (+z)
    return m;
  }
  add_quad(m, {-2, 0, 2}, {-0.6f, 0, 2}, {-0.6f, 3, 2}, {-2, 3, 2}, inside);
  add_quad(m, {0.6f, 0, 2}, {2, 0, 2}, {2, 3, 2}, {0.6f, 3, 2}, inside);
  add_quad(m, {-0.6f, 2.2f, 2}, {0.6f, 2.2f, 2}, {0.6f, 3, 2}, {-0.6f, 3, 2}, inside);
  return m;
}

void add_room(Scene& s, bool doorway) {
  add_object(s, room_shell(doorway), lambert_material("room", glm::vec3(0.55f, 0.53f, 0.5f)));
  add_object(s, box_mesh("red_block", {-1.6f, 0.0f, -1.6f}, {-0.8f, 1.0f, -0.8f}), lambert_material("red_block", {0.7f, 0.15f, 0.12f}));
  add_object(s, box_mesh("green_block", {0.7f, 0.0f, -1.2f}, {1.5f, 0.6f, -0.4f}),
             lambert_material("green_block", {0.15f, 0.6f, 0.2f}));
  // The ceiling panel faces down, a little below the ceiling.
  Mesh light{"light"};
  add_quad(light, {-0.5f, 2.98f, -0.5f}, {0.5f, 2.98f, -0.5f}, {0.5f, 2.98f, 0.5f}, {-0.5f, 2.98f, 0.5f},
           {0.0f, 0.0f, 0.0f});
  add_object(s, std::move(light), emitter_material("light", glm::vec3(12.0f, 11.0f, 9.5f)));
}

void add_sun(Scene& s) {
  DirectionalLight sun;
  sun.name = "sun";
  sun.direction = glm::normalize(glm::vec3(0.4f, 1.0f, 0.3f));
  sun.color = glm::vec3(1.0f, 0.96f, 0.9f);
  sun.illuminance = 3.0f;
  s.directional_lights.push_back(sun);
}

}  // namespace

Scene make_cache_closed_room() {
  Scene s;
  s.name = "cache_closed_room";
  add_room(s, false);
  s.camera.position = {0.0f, 1.6f, 1.8f};
  s.camera.target = {0.0f, 1.0f, -2.0f};
  s.camera.vertical_fov_degrees = 70.0f;
  return s;
}

Scene make_cache_room_and_yard() {
  Scene s;
  s.name = "cache_room_and_yard";
  add_room(s, true);
  Mesh yard{"yard"};
  add_quad(yard, {-30, -0.01f, 2}, {30, -0.01f, 2}, {30, -0.01f, 62}, {-30, -0.01f, 62}, {0, 1, 30});
  add_object(s, std::move(yard), lambert_material("yard", glm::vec3(0.45f, 0.5f, 0.4f)));
  for (int i = 0; i < 8; ++i) {
    const float x = -21.0f + 6.0f * float(i), z = 14.0f + 3.0f * float(i % 3);
    add_object(s, box_mesh("yard_block_" + std::to_string(i), {x, 0.0f, z}, {x + 2.0f, 1.0f + 0.5f * float(i % 4), z + 2.0f}),
               lambert_material("yard_block_" + std::to_string(i), glm::vec3(0.6f, 0.55f, 0.5f)));
  }
  add_sun(s);
  s.camera.position = {0.0f, 1.6f, 1.0f};
  s.camera.target = {0.0f, 1.0f, -2.0f};
  s.camera.vertical_fov_degrees = 70.0f;
  return s;
}

Scene make_cache_open_field() {
  Scene s;
  s.name = "cache_open_field";
  Mesh ground{"ground"};
  add_quad(ground, {-200, 0, -200}, {200, 0, -200}, {200, 0, 200}, {-200, 0, 200}, {0, 1, 0});
  add_object(s, std::move(ground), lambert_material("ground", glm::vec3(0.4f, 0.45f, 0.35f)));
  // Blocks on a 20 m grid out to 180 m: near ones fine cells, far ones coarse.
  int n = 0;
  for (int i = -9; i <= 9; ++i)
    for (int j = -9; j <= 9; ++j) {
      if ((i * 7 + j * 3) % 4 != 0) continue;
      const float x = 20.0f * float(i), z = 20.0f * float(j), h = 2.0f + float((i * i + j) % 5);
      const std::string name = "block_" + std::to_string(n++);
      add_object(s, box_mesh(name, {x - 2.0f, 0.0f, z - 2.0f}, {x + 2.0f, h, z + 2.0f}), lambert_material(name, glm::vec3(0.6f)));
    }
  add_sun(s);
  s.camera.position = {3.0f, 2.0f, 3.0f};
  s.camera.target = {40.0f, 0.0f, 60.0f};
  s.camera.vertical_fov_degrees = 60.0f;
  return s;
}

namespace {

// The wall's three parts (the wall, its end past the doorway, the lintel) as
// boxes `half_thickness` either side of z = 0, or, at 0, as single faces
// whose front looks into the lit room (z < 0).
void add_dividing_wall(Scene& s, float half_thickness) {
  const glm::vec3 wall_colour(0.6f, 0.6f, 0.6f);
  auto part = [&](const char* name, glm::vec2 lo, glm::vec2 hi) {
    if (half_thickness > 0.0f) {
      add_object(s, box_mesh(name, {lo.x, lo.y, -half_thickness}, {hi.x, hi.y, half_thickness}),
                 lambert_material(name, wall_colour));
      return;
    }
    Mesh m{name};
    add_quad(m, {lo.x, lo.y, 0.0f}, {hi.x, lo.y, 0.0f}, {hi.x, hi.y, 0.0f}, {lo.x, hi.y, 0.0f},
             {0.5f * (lo.x + hi.x), 0.5f * (lo.y + hi.y), -1.0f});
    add_object(s, std::move(m), lambert_material(name, wall_colour));
  };
  part("wall", {-3.0f, 0.0f}, {1.8f, 2.5f});
  part("wall_end", {2.6f, 0.0f}, {3.0f, 2.5f});
  part("lintel", {1.8f, 2.0f}, {2.6f, 2.5f});
}

// 6 × 2.5 × 4 m, split at z = 0 by a wall (2 cm, or one face); a 0.8 × 2 m doorway at its
// +x end lets a little light into the near room (z > 0), so the wall's near
// side is dark but not black in the path tracer. The panel over the far room
// is the only light.
Scene leak_rooms(const char* name, float wall_half_thickness) {
  Scene s;
  s.name = name;
  add_object(s, box_mesh("shell", {-3.0f, 0.0f, -2.0f}, {3.0f, 2.5f, 2.0f}, true),
             lambert_material("shell", glm::vec3(0.6f, 0.58f, 0.55f)));
  add_dividing_wall(s, wall_half_thickness);
  Mesh light{"light"};
  add_quad(light, {-1.5f, 2.48f, -1.5f}, {0.5f, 2.48f, -1.5f}, {0.5f, 2.48f, -0.5f}, {-1.5f, 2.48f, -0.5f},
           {-0.5f, 0.0f, -1.0f});
  add_object(s, std::move(light), emitter_material("light", glm::vec3(20.0f, 19.0f, 17.0f)));
  s.camera.position = {-1.0f, 1.3f, 1.9f};
  s.camera.target = {-0.6f, 0.8f, 0.0f};
  s.camera.vertical_fov_degrees = 70.0f;
  return s;
}

}  // namespace

Scene make_leak_thin_wall() { return leak_rooms("leak_thin_wall", 0.01f); }

// Bevy keys a hit's cell with the mesh's normal, never flipped (world_cache.hit_normal
// "vertex"): a ray from the dark room that hits this wall's back queries the
// lit side's cell.
Scene make_leak_zero_thickness_wall() { return leak_rooms("leak_zero_thickness_wall", 0.0f); }

}  // namespace gi
