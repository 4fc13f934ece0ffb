#include "core/scenes/mesh_builder.h"

namespace gi {

void add_quad(Mesh& mesh, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 facing_point, bool away) {
  const glm::vec3 n = glm::cross(b - a, c - a);
  const bool faces = glm::dot(n, facing_point - a) > 0.0f;
  const std::uint32_t base = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
  if (faces != away)
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  else
    mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
}

std::uint32_t add_object(Scene& scene, Mesh mesh, Material material, glm::mat4 transform) {
  Instance inst;
  inst.name = mesh.name;
  inst.mesh = static_cast<std::uint32_t>(scene.meshes.size());
  inst.material = static_cast<std::uint32_t>(scene.materials.size());
  inst.transform = transform;
  scene.meshes.push_back(std::move(mesh));
  scene.materials.push_back(std::move(material));
  scene.instances.push_back(inst);
  return static_cast<std::uint32_t>(scene.instances.size() - 1);
}

}  // namespace gi
