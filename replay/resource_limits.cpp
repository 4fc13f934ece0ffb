#include "replay/resource_limits.h"

#include <fmt/format.h>

#include "core/errors.h"

namespace gi {

std::uint64_t texel_bytes(const Scene& scene) {
  std::uint64_t bytes = 0;
  for (const TextureImage& i : scene.images) bytes += std::uint64_t(i.width) * i.height * 4;
  return bytes;
}

std::uint64_t estimated_gpu_bytes(const Scenario& scenario, const Scene& scene) {
  std::uint64_t triangles = 0, vertices = 0;
  for (const Mesh& m : scene.meshes) {
    triangles += m.triangle_count();
    vertices += m.positions.size();
  }
  const std::uint64_t pixels = std::uint64_t(scenario.resolution[0]) * scenario.resolution[1];
  // A textured scene adds its texels and a uv + tangent (32 bytes) per vertex.
  const std::uint64_t textures = scene.images.empty() ? 0 : texel_bytes(scene) + vertices * 32;
  return pixels * kBytesPerPixel + triangles * kBytesPerTriangle + scene.instances.size() * 256ull + textures;
}

void check_resource_limits(const Scenario& scenario, const Scene& scene, std::uint64_t heap_bytes,
                           std::uint64_t storage_range) {
  const std::string file = scenario.file.string();
  std::uint64_t triangles = 0;
  for (const Mesh& m : scene.meshes) triangles += m.triangle_count();
  if (triangles > kMaxTriangles)
    throw InputError(file, "/scene",
                     fmt::format("a scene of at most {} triangles; it has {}", kMaxTriangles, triangles));
  std::uint64_t lights = 0;
  for (const Instance& i : scene.instances) {
    const glm::vec3 e = scene.materials[i.material].emissive * i.emissive_scale;
    if (e.x > 0 || e.y > 0 || e.z > 0) lights += scene.meshes[i.mesh].triangle_count();
  }
  lights += scene.directional_lights.size();
  if (lights > kMaxLights)
    throw InputError(file, "/scene",
                     fmt::format("at most {} light triangles and directional lights; the scene has {}", kMaxLights,
                                 lights));
  const std::uint64_t texels = texel_bytes(scene);
  if (storage_range > 0 && texels > storage_range)
    throw InputError(file, "/scene",
                     fmt::format("textures whose texels fit one storage buffer of this device ({} MiB, "
                                 "maxStorageBufferRange); the scene's {} images need {} MiB as RGBA8",
                                 storage_range >> 20, scene.images.size(), texels >> 20));
  const std::uint64_t need = estimated_gpu_bytes(scenario, scene);
  if (heap_bytes > 0 && need > heap_bytes)
    throw InputError(file, "/resolution",
                     fmt::format("a scenario whose GPU buffers fit this device: about {} MiB needed at {}x{} with "
                                 "{} triangles, the largest memory heap has {} MiB",
                                 need >> 20, scenario.resolution[0], scenario.resolution[1], triangles,
                                 heap_bytes >> 20));
}

}  // namespace gi
