// Small helpers for generated scenes: quads and boxes with a chosen facing,
// and the few materials they use.
#pragma once
#include <string>

#include "core/scene.h"

namespace gi {

// Appends quad a-b-c-d (two triangles). The winding is chosen so that the
// front face looks towards `facing_point` (or away from it when away = true).
void add_quad(Mesh& mesh, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 facing_point,
              bool away = false);

// Adds mesh + material + instance and returns the instance index.
std::uint32_t add_object(Scene& scene, Mesh mesh, Material material, glm::mat4 transform = glm::mat4(1.0f));

// Axis-aligned box [lo, hi], faces outwards (a block) or inwards (a room's
// shell); open_bottom leaves out the y = lo face (a slab standing on a floor).
Mesh box_mesh(const std::string& name, glm::vec3 lo, glm::vec3 hi, bool inwards = false, bool open_bottom = false);

// A pure Lambert surface: reflectance 0 leaves no specular lobe (the Cornell
// box's data, and the world cache's own model of a surface).
Material lambert_material(const std::string& name, glm::vec3 albedo);

// A black Lambert surface whose front face emits `radiance`.
Material emitter_material(const std::string& name, glm::vec3 radiance);

// A metal (metallic 1): its base colour is its F0.
Material metal_material(const std::string& name, glm::vec3 base_color, float perceptual_roughness);

}  // namespace gi
