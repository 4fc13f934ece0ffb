// Small helpers for generated scenes: quads and boxes with a chosen facing.
#pragma once
#include "core/scene.h"

namespace gi {

// Appends quad a-b-c-d (two triangles). The winding is chosen so that the
// front face looks towards `facing_point` (or away from it when away = true).
void add_quad(Mesh& mesh, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 facing_point,
              bool away = false);

// Adds mesh + material + instance and returns the instance index.
std::uint32_t add_object(Scene& scene, Mesh mesh, Material material, glm::mat4 transform = glm::mat4(1.0f));

}  // namespace gi
