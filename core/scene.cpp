#include "core/scene.h"

namespace gi {

std::vector<bool> Scene::visible_instances() const {
  std::vector<bool> v;
  v.reserve(instances.size());
  for (const Instance& i : instances) v.push_back(i.visible);
  return v;
}

std::optional<std::uint32_t> Scene::find_instance(const std::string& n) const {
  for (std::uint32_t i = 0; i < instances.size(); ++i)
    if (instances[i].name == n) return i;
  return std::nullopt;
}

std::optional<std::uint32_t> Scene::find_directional_light(const std::string& n) const {
  for (std::uint32_t i = 0; i < directional_lights.size(); ++i)
    if (directional_lights[i].name == n) return i;
  return std::nullopt;
}

std::size_t Scene::triangle_count() const {
  std::size_t n = 0;
  for (const Instance& inst : instances)
    if (inst.visible) n += meshes[inst.mesh].triangle_count();
  return n;
}

}  // namespace gi
