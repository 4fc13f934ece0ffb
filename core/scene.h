// The scene model: what a scenario describes and both renderers draw.
// Units are metres and radiometric (emissive radiance in W/(sr·m²)-like units,
// directional illuminance as irradiance at normal incidence); there is no
// exposure in the harness: images are linear HDR.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace gi {

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty, or one per position
  std::vector<std::uint32_t> indices;  // triangle list, counter-clockwise = front
  std::vector<glm::vec2> uvs;       // TEXCOORD_0: empty, or one per position
  std::vector<glm::vec4> tangents;  // glTF TANGENT: xyz object-space tangent, w = ±1 the
                                    // bitangent's sign; empty, or one per position
  std::size_t triangle_count() const { return indices.size() / 3; }
};

// A decoded texture image: RGBA8, rows top to bottom (glTF's uv (0, 0) is the
// image's top-left corner).
struct TextureImage {
  std::string name;
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width · height · 4 bytes
};

// A material's reference to a texture (glTF textureInfo with its sampler's
// wrap modes and KHR_texture_transform).
struct TextureRef {
  std::int32_t image = -1;  // into Scene::images; -1: no texture
  std::uint32_t wrap_s = 0, wrap_t = 0;  // core/shared/texture_sampling.h TEXTURE_WRAP_*
  glm::vec2 offset{0.0f};
  float rotation = 0.0f;  // radians, counter-clockwise
  glm::vec2 scale{1.0f};
  float normal_scale = 1.0f;  // normalTexture.scale
  bool present() const { return image >= 0; }
};

struct Material {
  std::string name;
  glm::vec3 base_color{0.8f};
  float metallic = 0.0f;
  float perceptual_roughness = 0.5f;
  float reflectance = 0.5f;  // 0.5 → F0 = 4% (Filament's convention)
  glm::vec3 emissive{0.0f};  // radiance of the front face
  // glTF's rule: each factor above times its texture (base colour and
  // emissive sRGB; metallic in B, roughness in G).
  TextureRef base_color_texture, metallic_roughness_texture, normal_texture, emissive_texture;
  bool textured() const {
    return base_color_texture.present() || metallic_roughness_texture.present() || normal_texture.present() ||
           emissive_texture.present();
  }
};

struct Instance {
  std::string name;
  std::uint32_t mesh = 0;
  std::uint32_t material = 0;
  glm::mat4 transform{1.0f};     // object → world
  // Object → world at the previous frame, where it differs from `transform`
  // (Bevy's PreviousGlobalTransform, v0.18.0:bevy_pbr/src/prepass/mod.rs:124):
  // set by apply_events, read by the G-buffer's motion vectors. None: the
  // instance did not move since the previous frame, or did not exist then.
  std::optional<glm::mat4> previous_transform;
  glm::vec3 emissive_scale{1.0f};  // light events scale the material's emission
  bool visible = true;           // despawned instances stay in the list, hidden
  // Hidden by remove_raytracing_mesh (Bevy: RaytracingMesh3d removed, the
  // entity kept). Solari before v0.19.1 never took such an instance out of
  // its ray-traced scene (#24764); FrameLoop keeps it there under
  // scene.raytracing_mesh_removal "ignored".
  bool raytracing_mesh_removed = false;
};

struct DirectionalLight {
  std::string name;
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  // unit vector towards the light
  glm::vec3 color{1.0f};
  float illuminance = 1.0f;       // irradiance on a surface facing the light
  float angular_radius = 0.00465f;  // radians (the sun: 0.266°)
  bool enabled = true;
};

struct Camera {
  glm::vec3 position{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float vertical_fov_degrees = 40.0f;
};

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<TextureImage> images;  // what the materials' TextureRefs point at
  std::vector<Instance> instances;
  std::vector<DirectionalLight> directional_lights;
  Camera camera;
  // Radiance where a camera ray hits nothing (Bevy's ClearColor): shown, not
  // lit by. Both renderers add it at primary misses only.
  glm::vec3 background{0.0f};
  // Which Bevy release's material model shades every material (brdf.h's
  // BRDF_*; the profile's brdf.model, set by apply_material_model). Both
  // renderers read it from the flattened materials.
  std::uint32_t brdf_model = 0;
  std::vector<std::string> warnings;  // stated simplifications made on import

  std::optional<std::uint32_t> find_instance(const std::string& name) const;
  // Each instance's visible flag, in instance order (what the GPU backends'
  // update_scene and the ray sets take; Embree's bytes: instance_visibility).
  std::vector<bool> visible_instances() const;
  std::optional<std::uint32_t> find_directional_light(const std::string& name) const;
  std::size_t triangle_count() const;  // over visible instances
};

}  // namespace gi
