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

Mesh box_mesh(const std::string& name, glm::vec3 lo, glm::vec3 hi, bool inwards, bool open_bottom) {
  Mesh m{name};
  const glm::vec3 c = 0.5f * (lo + hi);
  auto P = [&](int x, int y, int z) { return glm::vec3(x ? hi.x : lo.x, y ? hi.y : lo.y, z ? hi.z : lo.z); };
  const bool away = !inwards;
  add_quad(m, P(0, 0, 0), P(1, 0, 0), P(1, 1, 0), P(0, 1, 0), c, away);
  add_quad(m, P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1), c, away);
  add_quad(m, P(0, 0, 0), P(0, 1, 0), P(0, 1, 1), P(0, 0, 1), c, away);
  add_quad(m, P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1), c, away);
  if (!open_bottom) add_quad(m, P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1), c, away);
  add_quad(m, P(0, 1, 0), P(1, 1, 0), P(1, 1, 1), P(0, 1, 1), c, away);
  return m;
}

Material lambert_material(const std::string& name, glm::vec3 albedo) {
  Material m;
  m.name = name;
  m.base_color = albedo;
  m.perceptual_roughness = 1.0f;
  m.reflectance = 0.0f;
  return m;
}

Material emitter_material(const std::string& name, glm::vec3 radiance) {
  Material m = lambert_material(name, glm::vec3(0.0f));
  m.emissive = radiance;
  return m;
}

Material metal_material(const std::string& name, glm::vec3 base_color, float perceptual_roughness) {
  Material m;
  m.name = name;
  m.base_color = base_color;
  m.metallic = 1.0f;
  m.perceptual_roughness = perceptual_roughness;
  return m;
}

}  // namespace gi
