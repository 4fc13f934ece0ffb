#include "core/scenes/gi_scenes.h"

#include <cmath>

#include "core/scenes/mesh_builder.h"

namespace gi {
namespace {

// An axis-aligned room [lo, hi] with inward faces, one mesh per wall (own
// materials), and a square ceiling emitter of half-size `light` just below it.
void add_room(Scene& s, glm::vec3 lo, glm::vec3 hi, float light, glm::vec3 radiance) {
  const glm::vec3 c = 0.5f * (lo + hi);
  auto P = [&](int x, int y, int z) { return glm::vec3(x ? hi.x : lo.x, y ? hi.y : lo.y, z ? hi.z : lo.z); };
  struct Wall { const char* name; glm::vec3 a, b, cc, d, albedo; };
  const Wall walls[] = {
      {"floor", P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1), glm::vec3(0.7f)},
      {"ceiling", P(0, 1, 0), P(1, 1, 0), P(1, 1, 1), P(0, 1, 1), glm::vec3(0.7f)},
      {"back", P(0, 0, 0), P(1, 0, 0), P(1, 1, 0), P(0, 1, 0), glm::vec3(0.7f)},
      {"front", P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1), glm::vec3(0.7f)},
      {"left", P(0, 0, 0), P(0, 1, 0), P(0, 1, 1), P(0, 0, 1), glm::vec3(0.7f, 0.2f, 0.2f)},
      {"right", P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1), glm::vec3(0.2f, 0.6f, 0.25f)},
  };
  for (const Wall& w : walls) {
    Mesh m{w.name};
    add_quad(m, w.a, w.b, w.cc, w.d, c);
    add_object(s, std::move(m), lambert_material(w.name, w.albedo));
  }
  Mesh l{"light"};
  const float y = hi.y - 0.01f;
  add_quad(l, {c.x - light, y, c.z - light}, {c.x + light, y, c.z - light}, {c.x + light, y, c.z + light},
           {c.x - light, y, c.z + light}, {c.x, lo.y, c.z});
  add_object(s, std::move(l), emitter_material("light", radiance));
}

}  // namespace

Scene make_gi_corners() {
  Scene s;
  s.name = "gi_corners";
  add_room(s, {-1.0f, 0.0f, -1.0f}, {1.0f, 2.0f, 1.0f}, 0.25f, glm::vec3(12.0f));
  // A wedge: two walls meeting at x = 0.2 on the floor, 5° apart, their
  // inner faces towards the camera.
  const float h = 1.2f, len = 0.8f, half_angle = 0.0436f;  // 2.5° each side of the -z axis
  Mesh wedge{"wedge"};
  const glm::vec3 apex(0.2f, 0.0f, -0.9f), apex_top(0.2f, h, -0.9f);
  const glm::vec3 a(0.2f - len * std::sin(half_angle), 0.0f, -0.9f + len * std::cos(half_angle));
  const glm::vec3 b(0.2f + len * std::sin(half_angle), 0.0f, -0.9f + len * std::cos(half_angle));
  const glm::vec3 inside(0.2f, 0.5f * h, -0.9f + 0.5f * len);
  add_quad(wedge, apex, a, a + glm::vec3(0, h, 0), apex_top, inside);
  add_quad(wedge, apex, b, b + glm::vec3(0, h, 0), apex_top, inside);
  add_object(s, std::move(wedge), lambert_material("wedge", glm::vec3(0.75f)));
  // A thin wall, 1 cm thick, standing free on the floor.
  add_object(s, box_mesh("thin_wall", {-0.7f, 0.0f, -0.3f}, {-0.1f, 1.0f, -0.29f}, false, /*open_bottom=*/true),
             lambert_material("thin_wall", glm::vec3(0.6f)));
  s.camera.position = {-0.3f, 1.0f, 0.9f};
  s.camera.target = {0.1f, 0.4f, -0.8f};
  s.camera.vertical_fov_degrees = 55.0f;
  return s;
}

Scene make_gi_mirror() {
  Scene s;
  s.name = "gi_mirror";
  add_room(s, {-1.0f, 0.0f, -1.0f}, {1.0f, 2.0f, 1.0f}, 0.3f, glm::vec3(10.0f));
  Mesh mirror{"mirror"};
  add_quad(mirror, {-0.6f, 0.3f, -0.98f}, {0.6f, 0.3f, -0.98f}, {0.6f, 1.5f, -0.98f}, {-0.6f, 1.5f, -0.98f},
           {0.0f, 1.0f, 0.0f});
  add_object(s, std::move(mirror), metal_material("mirror", glm::vec3(0.95f), 0.0f));
  Mesh glossy{"glossy_floor_tile"};
  add_quad(glossy, {-0.9f, 0.001f, -0.9f}, {0.9f, 0.001f, -0.9f}, {0.9f, 0.001f, 0.2f}, {-0.9f, 0.001f, 0.2f},
           {0.0f, 1.0f, 0.0f});
  Material g = lambert_material("glossy", glm::vec3(0.3f, 0.3f, 0.5f));
  g.perceptual_roughness = 0.3f;
  g.reflectance = 0.5f;
  add_object(s, std::move(glossy), g);
  add_object(s, box_mesh("block", {0.3f, 0.0f, -0.2f}, {0.7f, 0.5f, 0.2f}, false, /*open_bottom=*/true),
             lambert_material("block", glm::vec3(0.8f, 0.7f, 0.3f)));
  s.camera.position = {0.0f, 1.0f, 0.95f};
  s.camera.target = {0.0f, 0.8f, -1.0f};
  s.camera.vertical_fov_degrees = 60.0f;
  return s;
}

Scene make_gi_hard_cases() {
  Scene s;
  s.name = "gi_hard_cases";
  // A long floor seen at a grazing angle, a back wall.
  Mesh floor{"floor"};
  add_quad(floor, {-2.0f, 0.0f, -20.0f}, {2.0f, 0.0f, -20.0f}, {2.0f, 0.0f, 1.0f}, {-2.0f, 0.0f, 1.0f}, {0, 1, 0});
  add_object(s, std::move(floor), lambert_material("floor", glm::vec3(0.6f)));
  Mesh back{"back"};
  add_quad(back, {-2.0f, 0.0f, -20.0f}, {2.0f, 0.0f, -20.0f}, {2.0f, 3.0f, -20.0f}, {-2.0f, 3.0f, -20.0f}, {0, 1, 0});
  add_object(s, std::move(back), lambert_material("back", glm::vec3(0.5f)));
  // Emitters 1e-4, 1, 1e6 (the last tiny: 2 cm) facing down.
  const float radiance[] = {1e-4f, 1.0f, 1e6f};
  const float half[] = {0.5f, 0.5f, 0.01f};
  for (int i = 0; i < 3; ++i) {
    const float x = -1.2f + 1.2f * float(i), z = -4.0f;
    const std::string name = "light_" + std::to_string(i);
    Mesh l{name};
    add_quad(l, {x - half[i], 2.0f, z - half[i]}, {x + half[i], 2.0f, z - half[i]}, {x + half[i], 2.0f, z + half[i]},
             {x - half[i], 2.0f, z + half[i]}, {x, 0.0f, z});
    add_object(s, std::move(l), emitter_material(name, glm::vec3(radiance[i])));
  }
  // A zero-roughness mirror standing on the floor.
  Mesh mirror{"mirror"};
  add_quad(mirror, {-1.5f, 0.0f, -8.0f}, {-0.5f, 0.0f, -7.0f}, {-0.5f, 1.5f, -7.0f}, {-1.5f, 1.5f, -8.0f},
           {0.0f, 0.5f, 0.0f});
  add_object(s, std::move(mirror), metal_material("mirror", glm::vec3(0.9f), 0.0f));
  // Degenerate and sliver triangles above the floor.
  Mesh odd{"degenerate_and_slivers"};
  const glm::vec3 p(0.5f, 0.3f, -3.0f);
  odd.positions = {p, p, p,                                                       // zero area: one point
                   p + glm::vec3(0, 0.2f, 0), p + glm::vec3(1, 0.2f, 0), p + glm::vec3(2, 0.2f, 0),  // collinear
                   p + glm::vec3(0, 0.4f, 0), p + glm::vec3(1, 0.4f, 0), p + glm::vec3(0.5f, 0.4001f, 0.0f),  // sliver 1e4
                   p + glm::vec3(0, 0.5f, 0), p + glm::vec3(0, 0.5f, -1), p + glm::vec3(1e-4f, 0.5f, -0.5f)};
  odd.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  add_object(s, std::move(odd), lambert_material("odd", glm::vec3(0.8f)));
  s.camera.position = {0.0f, 0.15f, 0.8f};
  s.camera.target = {0.0f, 0.05f, -10.0f};
  s.camera.vertical_fov_degrees = 50.0f;
  return s;
}

Scene make_gi_indirect_shadow() {
  Scene s;
  s.name = "gi_indirect_shadow";
  Mesh floor{"floor"};
  add_quad(floor, {-3.0f, 0.0f, -1.0f}, {3.0f, 0.0f, -1.0f}, {3.0f, 0.0f, 4.0f}, {-3.0f, 0.0f, 4.0f}, {0, 1, 0});
  add_object(s, std::move(floor), lambert_material("floor", glm::vec3(0.7f)));
  // The bright wall the floor beyond z 0.6 is lit by.
  Mesh wall{"wall"};
  add_quad(wall, {-2.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {2.0f, 2.5f, 0.0f}, {-2.0f, 2.5f, 0.0f}, {0, 1, 1});
  add_object(s, std::move(wall), lambert_material("wall", glm::vec3(0.9f)));
  // A wall washer: it faces the wall (-z) from z 0.6, so nothing at z > 0.6
  // sees its emitting face; its back is black.
  Mesh light{"light"};
  add_quad(light, {-1.2f, 1.4f, 0.6f}, {1.2f, 1.4f, 0.6f}, {1.2f, 2.2f, 0.6f}, {-1.2f, 2.2f, 0.6f}, {0, 1.8f, 0});
  add_object(s, std::move(light), emitter_material("light", glm::vec3(12.0f, 11.0f, 10.0f)));
  // The occluder: a black screen 1 m tall at z 0.8, which scenarios park out
  // of sight and move in; behind it the floor sees none of the wall.
  add_object(s, box_mesh("screen", {-1.0f, 0.0f, 0.8f}, {1.0f, 1.0f, 0.82f}, false, true),
             lambert_material("screen", glm::vec3(0.0f)));
  // A black shell closes the scene: it reflects nothing, as an open sky
  // would, but a GI ray that leaves finds a surface. Solari gives a miss no
  // confidence (restir_gi.empty_samples), which in an open scene brightens
  // the floor by about the inverse of the fraction of rays that hit.
  add_object(s, box_mesh("shell", {-3.5f, -0.05f, -0.5f}, {3.5f, 3.5f, 4.5f}, true),
             lambert_material("shell", glm::vec3(0.0f)));
  s.camera.position = {0.0f, 1.5f, 3.6f};
  s.camera.target = {0.0f, 0.2f, 1.0f};
  s.camera.vertical_fov_degrees = 55.0f;
  return s;
}

Scene make_gi_headon_panel() {
  Scene s;
  s.name = "gi_headon_panel";
  add_room(s, {-1.0f, 0.0f, -1.0f}, {1.0f, 2.0f, 1.0f}, 0.3f, glm::vec3(10.0f));
  // A glossy metal panel (α 0.0025, above Bevy's 0.001 mirror threshold, so
  // the full lobe is evaluated), its normal off every axis: an axis-aligned
  // one rounds its dots to exactly 1 and never above.
  const glm::vec3 c(0.0f, 1.0f, -0.3f);
  const glm::vec3 n = glm::normalize(glm::vec3(1.0f, 1.0f, 1.0f));
  const glm::vec3 t = glm::normalize(glm::cross(n, glm::vec3(0.0f, 1.0f, 0.0f)));
  const glm::vec3 b = glm::cross(n, t);
  Mesh panel{"panel"};
  add_quad(panel, c - 0.3f * t - 0.3f * b, c + 0.3f * t - 0.3f * b, c + 0.3f * t + 0.3f * b, c - 0.3f * t + 0.3f * b,
           c + n);
  add_object(s, std::move(panel), metal_material("panel", glm::vec3(0.9f), 0.05f));
  // Head-on through a narrow lens: each pixel spans 4e-4 rad, so the
  // reflected ray leaves within about 1e-3 rad of the view ray, where L·H
  // can round above 1.
  s.camera.position = c + 0.6f * n;
  s.camera.target = c;
  s.camera.vertical_fov_degrees = 1.5f;
  return s;
}

Scene make_gi_mirror_shadow_stripe() {
  Scene s;
  s.name = "gi_mirror_shadow_stripe";
  Mesh floor{"floor"};
  add_quad(floor, {-2.0f, 0.0f, -2.5f}, {2.0f, 0.0f, -2.5f}, {2.0f, 0.0f, 3.0f}, {-2.0f, 0.0f, 3.0f}, {0, 1, 0});
  add_object(s, std::move(floor), lambert_material("floor", glm::vec3(0.7f)));
  // A mirror leaning forward, so that the camera, which sees nothing else,
  // sees the floor in it; a black board behind it.
  Mesh mirror{"mirror"};
  add_quad(mirror, {-1.2f, 0.0f, -1.2f}, {1.2f, 0.0f, -1.2f}, {1.2f, 0.8f, -1.05f}, {-1.2f, 0.8f, -1.05f},
           {0.0f, 0.4f, 0.0f});
  add_object(s, std::move(mirror), metal_material("mirror", glm::vec3(0.95f), 0.0f));
  Mesh board{"board"};
  add_quad(board, {-1.2f, 0.0f, -1.21f}, {1.2f, 0.0f, -1.21f}, {1.2f, 0.8f, -1.06f}, {-1.2f, 0.8f, -1.06f},
           {0.0f, 0.4f, -3.0f});
  add_object(s, std::move(board), lambert_material("board", glm::vec3(0.0f)));
  // A small light behind the mirror's plane and above its top: it lights the
  // floor in front, and no ray from it reaches the mirror's face (no caustic
  // that the path tracer would find only by chance).
  Mesh light{"light"};
  add_quad(light, {-0.05f, 2.8f, -2.25f}, {0.05f, 2.8f, -2.25f}, {0.05f, 2.8f, -2.15f}, {-0.05f, 2.8f, -2.15f},
           {0.0f, 0.0f, -2.2f});
  add_object(s, std::move(light), emitter_material("light", glm::vec3(3000.0f)));
  // A bar 30 cm deep, half a metre above the floor: a shadow stripe about
  // 37 cm wide around z = -0.3, inside the mirror's view; the cache's cells
  // there (0.18's 0.25 m, grown with distance) span its edges.
  add_object(s, box_mesh("bar", {-1.5f, 0.45f, -0.79f}, {1.5f, 0.55f, -0.49f}), lambert_material("bar", glm::vec3(0.5f)));
  // The black shell: no GI ray leaves (see gi_indirect_shadow).
  add_object(s, box_mesh("shell", {-3.0f, -0.05f, -3.0f}, {3.0f, 3.2f, 3.5f}, true),
             lambert_material("shell", glm::vec3(0.0f)));
  s.camera.position = {0.0f, 1.0f, 2.4f};
  s.camera.target = {0.0f, 0.4f, -1.125f};
  s.camera.vertical_fov_degrees = 11.0f;
  return s;
}

}  // namespace gi
