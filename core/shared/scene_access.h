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
// No include guard on purpose (C++ includes it into each bridge struct);
// GLSL includes it once.

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
  s.material = inst.material;
  GpuMaterial m = scene_material(inst.material);
  s.emissive = vec3(m.emissive_perceptual_roughness) * vec3(inst.emissive_scale);
  return s;
}

GI_FN SurfacePoint surface_at_hit(Hit h) { return surface_at(h.instance, h.primitive, h.barycentrics); }
