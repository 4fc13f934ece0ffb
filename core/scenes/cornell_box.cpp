#include "core/scenes/cornell_box.h"

#include "core/scenes/mesh_builder.h"

namespace gi {
namespace {

constexpr float mm = 0.001f;

// The blocks' faces, each listed as in the data set (top first).
void add_block(Mesh& mesh, const glm::vec3 (&q)[5][4]) {
  glm::vec3 centre(0.0f);
  for (const auto& face : q)
    for (const glm::vec3& p : face) centre += p / 20.0f;
  for (const auto& face : q) add_quad(mesh, face[0], face[1], face[2], face[3], centre, /*away=*/true);
}

}  // namespace

Scene make_cornell_box(const CornellBoxOptions& o) {
  // The data set's millimetres, times the scale.
  const float unit = mm * o.scale;
  auto P = [unit](float x, float y, float z) { return glm::vec3(x, y, z) * unit; };
  Scene s;
  s.name = "cornell_box";
  const glm::vec3 inside = P(278.0f, 274.4f, 279.6f);
  const float k = o.albedo_scale;
  const glm::vec3 white = glm::vec3(0.725f, 0.71f, 0.68f) * k;

  Mesh room{"floor_ceiling_back"};
  add_quad(room, P(552.8f, 0, 0), P(0, 0, 0), P(0, 0, 559.2f), P(549.6f, 0, 559.2f), inside);
  add_quad(room, P(556, 548.8f, 0), P(556, 548.8f, 559.2f), P(0, 548.8f, 559.2f), P(0, 548.8f, 0), inside);
  add_quad(room, P(549.6f, 0, 559.2f), P(0, 0, 559.2f), P(0, 548.8f, 559.2f), P(556, 548.8f, 559.2f), inside);
  add_object(s, std::move(room), lambert_material("white", white));

  Mesh red{"red_wall"};
  add_quad(red, P(552.8f, 0, 0), P(549.6f, 0, 559.2f), P(556, 548.8f, 559.2f), P(556, 548.8f, 0), inside);
  add_object(s, std::move(red), lambert_material("red", glm::vec3(0.63f, 0.065f, 0.05f) * k));

  Mesh green{"green_wall"};
  add_quad(green, P(0, 0, 559.2f), P(0, 0, 0), P(0, 548.8f, 0), P(0, 548.8f, 559.2f), inside);
  add_object(s, std::move(green), lambert_material("green", glm::vec3(0.14f, 0.45f, 0.091f) * k));

  if (o.blocks) {
    const glm::vec3 short_block[5][4] = {
        {P(130, 165, 65), P(82, 165, 225), P(240, 165, 272), P(290, 165, 114)},
        {P(290, 0, 114), P(290, 165, 114), P(240, 165, 272), P(240, 0, 272)},
        {P(130, 0, 65), P(130, 165, 65), P(290, 165, 114), P(290, 0, 114)},
        {P(82, 0, 225), P(82, 165, 225), P(130, 165, 65), P(130, 0, 65)},
        {P(240, 0, 272), P(240, 165, 272), P(82, 165, 225), P(82, 0, 225)}};
    const glm::vec3 tall_block[5][4] = {
        {P(423, 330, 247), P(265, 330, 296), P(314, 330, 456), P(472, 330, 406)},
        {P(423, 0, 247), P(423, 330, 247), P(472, 330, 406), P(472, 0, 406)},
        {P(472, 0, 406), P(472, 330, 406), P(314, 330, 456), P(314, 0, 456)},
        {P(314, 0, 456), P(314, 330, 456), P(265, 330, 296), P(265, 0, 296)},
        {P(265, 0, 296), P(265, 330, 296), P(423, 330, 247), P(423, 0, 247)}};
    Mesh sb{"short_block"};
    add_block(sb, short_block);
    add_object(s, std::move(sb), lambert_material("short_block", white));
    Mesh tb{"tall_block"};
    add_block(tb, tall_block);
    add_object(s, std::move(tb), lambert_material("tall_block", white));
  }

  // The light sits 0.5 mm below the ceiling (the data set cuts a hole instead)
  // and faces down.
  Mesh light{"light"};
  const float y = 548.3f;
  add_quad(light, P(343, y, 227), P(343, y, 332), P(213, y, 332), P(213, y, 227), P(278, 0, 279.5f));
  Material emitter = lambert_material("light", glm::vec3(0.78f));
  emitter.emissive = glm::vec3(17.0f, 12.0f, 4.0f) * o.light_scale;
  add_object(s, std::move(light), emitter);

  s.camera.position = P(278, 273, -800);
  s.camera.target = P(278, 273, -799);
  s.camera.up = glm::vec3(0, 1, 0);
  s.camera.vertical_fov_degrees = 39.3077f;
  return s;
}

}  // namespace gi
