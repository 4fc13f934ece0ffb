// Surface reconstruction from a hit, shared by the GPU passes and the Embree
// reference. This file is a *bridge-included* file: the includer first
// defines the scene accessors below, then includes it — at file scope in GLSL,
// inside a struct body in C++ (the functions become members that see the
// struct's accessors). RTXDI's RAB_* bridge follows the same idea.
//
// Required accessors:
//   GpuInstance scene_instance(uint i);   GpuMaterial scene_material(uint i);
//   GpuVertex   scene_vertex(uint i);     uint        scene_index(uint i);
//   GpuLight    scene_light(uint i);      uint        scene_light_count();
//   uint        scene_directional_light_count();
//   GpuVertexAttributes scene_vertex_attributes(uint i);    (textured materials only)
//   GpuMaterialTextures scene_material_textures(uint i);
//   GpuTextureImage     scene_texture_image(uint i);
//   uint                scene_texel(uint i);                 RGBA8 (texture_sampling.h)
// No include guard on purpose (C++ includes it into each bridge struct);
// GLSL includes it once.

// A texture slot's value at uv (texture_sampling.h: mip 0, bilinear).
GI_FN vec4 sample_texture(GpuTextureSlot slot, vec2 uv, bool srgb) {
  BilinearFootprint f = bilinear_footprint(scene_texture_image(slot.image_wrap.x), slot, texture_transform(slot, uv));
  return bilinear_blend(decode_texel(scene_texel(f.texel.x), srgb), decode_texel(scene_texel(f.texel.y), srgb),
                        decode_texel(scene_texel(f.texel.z), srgb), decode_texel(scene_texel(f.texel.w), srgb),
                        f.weight);
}

// glTF's rule: each factor times its texture. The normal map bends the
// interpolated vertex normal (the geometric one on meshes without normals);
// the tangent follows the object-to-world transform, its sign flips with a
// mirroring one (as Bevy's mesh_tangent_local_to_world).
GI_FN void apply_material_textures(INOUT(SurfacePoint) s, GpuInstance inst, uint base, vec2 bary, float b0) {
  GpuMaterialTextures t = scene_material_textures(s.material);
  uint i0 = inst.first_vertex + scene_index(base);
  uint i1 = inst.first_vertex + scene_index(base + 1u);
  uint i2 = inst.first_vertex + scene_index(base + 2u);
  GpuVertexAttributes a0 = scene_vertex_attributes(i0);
  GpuVertexAttributes a1 = scene_vertex_attributes(i1);
  GpuVertexAttributes a2 = scene_vertex_attributes(i2);
  vec2 uv = b0 * vec2(a0.uv) + bary.x * vec2(a1.uv) + bary.y * vec2(a2.uv);
  GpuTextureSlot slot = t.slots[TEXTURE_SLOT_BASE_COLOR];
  if (slot.image_wrap.x != TEXTURE_NONE) {
    vec4 c = sample_texture(slot, uv, true);
    s.base_color_metallic = vec4(vec3(s.base_color_metallic) * vec3(c), s.base_color_metallic.w);
  }
  slot = t.slots[TEXTURE_SLOT_METALLIC_ROUGHNESS];
  if (slot.image_wrap.x != TEXTURE_NONE) {
    vec4 c = sample_texture(slot, uv, false);
    s.perceptual_roughness *= c.y;
    s.base_color_metallic.w *= c.z;
  }
  slot = t.slots[TEXTURE_SLOT_EMISSIVE];
  if (slot.image_wrap.x != TEXTURE_NONE) s.emissive *= vec3(sample_texture(slot, uv, true));
#if NORMAL_MAP_DECODE != 0
  slot = t.slots[TEXTURE_SLOT_NORMAL];
  if (slot.image_wrap.x != TEXTURE_NONE && a0.tangent.w != 0.0f) {
    vec3 tangent = b0 * vec3(a0.tangent) + bary.x * vec3(a1.tangent) + bary.y * vec3(a2.tangent);
    tangent = mat3(inst.object_to_world) * tangent;
    float sign = a0.tangent.w * (determinant(mat3(inst.object_to_world)) < 0.0f ? -1.0f : 1.0f);
    vec3 texel = vec3(sample_texture(slot, uv, false));
    float tangent_length = length(tangent);
    if (tangent_length > 0.0f) s.mesh_tangent = vec4(tangent / tangent_length, sign);
#if NORMAL_MAP_DECODE == 1
    // Solari through v0.19.0: the texel itself, unscaled (#24880 fixed it).
    s.shading_normal = perturb_normal(s.shading_normal, tangent, sign, texel, 1.0f);
#else
    s.shading_normal = perturb_normal(s.shading_normal, tangent, sign, texel * 2.0f - vec3(1.0f), slot.transform_u.w);
#endif
  }
#endif
}

GI_FN SurfacePoint surface_at(uint instance_index, uint primitive, vec2 bary) {
  GpuInstance inst = scene_instance(instance_index);
  uint base = inst.first_index + 3u * primitive;
  GpuVertex v0 = scene_vertex(inst.first_vertex + scene_index(base));
  GpuVertex v1 = scene_vertex(inst.first_vertex + scene_index(base + 1u));
  GpuVertex v2 = scene_vertex(inst.first_vertex + scene_index(base + 2u));
  vec3 p0 = vec3(inst.object_to_world * v0.position);
  vec3 p1 = vec3(inst.object_to_world * v1.position);
  vec3 p2 = vec3(inst.object_to_world * v2.position);
  float b0 = 1.0f - bary.x - bary.y;

  SurfacePoint s;
  s.position = b0 * p0 + bary.x * p1 + bary.y * p2;
  vec3 e = cross(p1 - p0, p2 - p0);
  float len = length(e);
  s.area = 0.5f * len;
  s.geometric_normal = len > 0.0f ? e / len : vec3(0.0f, 0.0f, 1.0f);
  s.shading_normal = s.geometric_normal;
  if (v0.normal.w > 0.0f) {
    vec3 n = b0 * vec3(v0.normal) + bary.x * vec3(v1.normal) + bary.y * vec3(v2.normal);
    n = mat3(inst.normal_to_world) * n;
    float nl = length(n);
    if (nl > 0.0f) s.shading_normal = n / nl;
  }
  s.vertex_normal = s.shading_normal;
  s.material = inst.material;
  GpuMaterial m = scene_material(inst.material);
  s.emissive = vec3(m.emissive_perceptual_roughness) * vec3(inst.emissive_scale);
  s.base_color_metallic = m.base_color_metallic;
  s.perceptual_roughness = m.emissive_perceptual_roughness.w;
  s.mesh_tangent = vec4(0.0f);
  if (m.reflectance.z != 0.0f) apply_material_textures(s, inst, base, bary, b0);
  return s;
}

GI_FN SurfacePoint surface_at_hit(Hit h) { return surface_at(h.instance, h.primitive, h.barycentrics); }
