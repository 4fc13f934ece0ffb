#include "core/scene_flatten.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/shared/sampling.h"

namespace gi {
namespace {

// Spreads the low 10 bits of v so there are two zero bits between each.
std::uint32_t expand_bits(std::uint32_t v) {
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  v = (v * 0x00000005u) & 0x49249249u;
  return v;
}

std::uint32_t morton3(glm::vec3 unit) {
  glm::uvec3 q = glm::uvec3(glm::clamp(unit * 1024.0f, glm::vec3(0.0f), glm::vec3(1023.0f)));
  return (expand_bits(q.x) << 2) | (expand_bits(q.y) << 1) | expand_bits(q.z);
}

std::vector<std::uint32_t> morton_sorted_indices(const Mesh& mesh) {
  const std::size_t n = mesh.triangle_count();
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 extent = glm::max(hi - lo, glm::vec3(1e-20f));
  std::vector<std::uint32_t> code(n), order(n);
  for (std::size_t t = 0; t < n; ++t) {
    glm::vec3 c = (mesh.positions[mesh.indices[3 * t]] + mesh.positions[mesh.indices[3 * t + 1]] +
                   mesh.positions[mesh.indices[3 * t + 2]]) / 3.0f;
    code[t] = morton3((c - lo) / extent);
  }
  std::iota(order.begin(), order.end(), 0u);
  // Stable: equal codes keep file order, so the result is deterministic.
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });
  std::vector<std::uint32_t> sorted(3 * n);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) sorted[3 * t + k] = mesh.indices[3 * order[t] + k];
  return sorted;
}

shader::GpuTextureSlot flatten_texture_slot(const TextureRef& t) {
  shader::GpuTextureSlot slot{};
  // KHR_texture_transform: uv' = offset + R(rotation) · (scale ∘ uv), with
  // R = [cos sin; −sin cos], which its example (offset [0, 1], rotation π/2,
  // scale ½ → the lower-left quadrant turned clockwise) pins down.
  const float c = std::cos(t.rotation), s = std::sin(t.rotation);
  slot.transform_u = glm::vec4(c * t.scale.x, s * t.scale.y, t.offset.x, t.normal_scale);
  slot.transform_v = glm::vec4(-s * t.scale.x, c * t.scale.y, t.offset.y, 0.0f);
  slot.image_wrap = glm::uvec4(t.present() ? std::uint32_t(t.image) : shader::TEXTURE_NONE, t.wrap_s, t.wrap_t, 0u);
  return slot;
}

// Every image's texels in one array, RGBA8 packed R-low.
void flatten_images(const Scene& scene, FlatGeometry& g) {
  for (const TextureImage& image : scene.images) {
    GpuTextureImage gi{};
    gi.first_width_height = glm::uvec4(std::uint32_t(g.texels.size()), image.width, image.height, 0u);
    g.texture_images.push_back(gi);
    const std::size_t n = std::size_t(image.width) * image.height;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t* p = &image.rgba[4 * i];
      g.texels.push_back(std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
                         std::uint32_t(p[3]) << 24);
    }
  }
}

}  // namespace

FlatGeometry flatten_geometry(const Scene& scene) {
  FlatGeometry g;
  for (const Mesh& mesh : scene.meshes) {
    MeshRange r;
    r.first_index = static_cast<std::uint32_t>(g.indices.size());
    r.first_vertex = static_cast<std::uint32_t>(g.vertices.size());
    r.triangle_count = static_cast<std::uint32_t>(mesh.triangle_count());
    r.vertex_count = static_cast<std::uint32_t>(mesh.positions.size());
    const bool has_normals = mesh.normals.size() == mesh.positions.size();
    const bool has_uvs = mesh.uvs.size() == mesh.positions.size();
    const bool has_tangents = mesh.tangents.size() == mesh.positions.size();
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      GpuVertex v;
      v.position = glm::vec4(mesh.positions[i], 1.0f);
      v.normal = has_normals ? glm::vec4(mesh.normals[i], 1.0f) : glm::vec4(0.0f);
      g.vertices.push_back(v);
      if (scene.images.empty()) continue;
      GpuVertexAttributes a{};
      a.uv = has_uvs ? glm::vec4(mesh.uvs[i], 0.0f, 0.0f) : glm::vec4(0.0f);
      a.tangent = has_tangents ? mesh.tangents[i] : glm::vec4(0.0f);
      g.vertex_attributes.push_back(a);
    }
    std::vector<std::uint32_t> sorted = morton_sorted_indices(mesh);
    g.indices.insert(g.indices.end(), sorted.begin(), sorted.end());
    g.meshes.push_back(r);
  }
  flatten_images(scene, g);
  return g;
}

FlatInstances flatten_instances(const Scene& scene, const FlatGeometry& geometry) {
  FlatInstances f;
  for (const Material& m : scene.materials) {
    GpuMaterial g;
    g.base_color_metallic = glm::vec4(m.base_color, m.metallic);
    g.emissive_perceptual_roughness = glm::vec4(m.emissive, m.perceptual_roughness);
    const bool textured = !scene.images.empty() && m.textured();
    g.reflectance = glm::vec4(m.reflectance, static_cast<float>(scene.brdf_model), textured ? 1.0f : 0.0f, 0.0f);
    f.materials.push_back(g);
    if (scene.images.empty()) continue;
    GpuMaterialTextures t{};
    t.slots[shader::TEXTURE_SLOT_BASE_COLOR] = flatten_texture_slot(m.base_color_texture);
    t.slots[shader::TEXTURE_SLOT_METALLIC_ROUGHNESS] = flatten_texture_slot(m.metallic_roughness_texture);
    t.slots[shader::TEXTURE_SLOT_NORMAL] = flatten_texture_slot(m.normal_texture);
    t.slots[shader::TEXTURE_SLOT_EMISSIVE] = flatten_texture_slot(m.emissive_texture);
    f.material_textures.push_back(t);
  }
  for (const DirectionalLight& d : scene.directional_lights) {
    if (!d.enabled || d.illuminance <= 0.0f || glm::dot(d.color, d.color) <= 0.0f) continue;
    GpuLight l{};
    l.kind = shader::LIGHT_KIND_DIRECTIONAL;
    const float omc = shader::one_minus_cos(d.angular_radius);
    l.direction = glm::vec4(glm::normalize(d.direction), omc);
    // Uniform radiance L over a cone of half-angle r gives normal irradiance
    // E = L * pi * sin²(r); so L = E / (pi sin² r).
    const float sin_r = std::sin(d.angular_radius);
    l.radiance = glm::vec4(d.color * (d.illuminance / (shader::PI * sin_r * sin_r)), 0.0f);
    f.lights.push_back(l);
  }
  f.directional_light_count = static_cast<std::uint32_t>(f.lights.size());
  for (std::uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const MeshRange& r = geometry.meshes[inst.mesh];
    GpuInstance g{};
    g.object_to_world = inst.transform;
    f.previous_object_to_world.push_back(inst.previous_transform.value_or(inst.transform));
    g.normal_to_world = glm::transpose(glm::inverse(inst.transform));
    g.first_index = r.first_index;
    g.first_vertex = r.first_vertex;
    g.triangle_count = r.triangle_count;
    g.material = inst.material;
    g.emissive_scale = glm::vec4(inst.emissive_scale, 0.0f);
    f.instances.push_back(g);
    const glm::vec3 emission = scene.materials[inst.material].emissive * inst.emissive_scale;
    if (inst.visible && r.triangle_count > 0 && glm::max(emission.x, glm::max(emission.y, emission.z)) > 0.0f) {
      GpuLight l{};
      l.kind = shader::LIGHT_KIND_EMISSIVE_MESH;
      l.instance = i;
      l.triangle_count = r.triangle_count;
      f.lights.push_back(l);
    }
  }
  return f;
}

GpuCamera make_gpu_camera(const Camera& camera, std::uint32_t width, std::uint32_t height) {
  const glm::vec3 forward = glm::normalize(camera.target - camera.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float tan_half = std::tan(glm::radians(camera.vertical_fov_degrees) * 0.5f);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  GpuCamera c;
  c.position = glm::vec4(camera.position, 1.0f);
  c.forward = glm::vec4(forward, 0.0f);
  c.right = glm::vec4(right * tan_half * aspect, 0.0f);
  c.up = glm::vec4(up * tan_half, 0.0f);
  return c;
}

FrameConstants frame_constants(const GpuCamera& camera, const GpuCamera& previous_camera, const FlatInstances& flat,
                               std::uint32_t width, std::uint32_t height, std::uint32_t frame, std::uint32_t seed,
                               std::uint32_t spp) {
  FrameConstants c{};
  c.camera = camera;
  c.previous_camera = previous_camera;
  c.resolution_frame = glm::uvec4(width, height, frame, seed);
  c.counts = glm::uvec4(static_cast<std::uint32_t>(flat.lights.size()), flat.directional_light_count, spp, frame * spp);
  return c;
}

}  // namespace gi
