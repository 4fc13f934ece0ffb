// G-buffer resolve: rebuilds each pixel's surface from the visibility buffer
// (surface_at() in core/shared/scene_access.h, barycentrics recomputed from
// the camera ray) and writes a GBufferTexel (gpu/shaders/gbuffer.h).
// The surface comes from the packed cluster ID alone (visibility x, decoded
// through the cluster table as decode_packed_visibility() does on the CPU);
// the instance channel (y) is never read here, so an aliased ID resolves to
// the wrong surface, as it did in Bevy. An ID naming no drawn triangle
// resolves to an empty texel.
//
// Motion vectors (temporal.motion_vectors): GBUFFER_MOTION_OBJECT (object,
// Bevy's prepass: v0.18.0:bevy_pbr/src/prepass/prepass.wgsl:158-164,197-205)
// project where the surface point was last frame, the same barycentrics on
// the triangle's vertices under the instance's previous transform, with
// previous_camera; without it (camera, the harness's earlier model) the
// point as it is now, so a moving object gets the camera's motion alone. An
// instance that did not move takes the point itself under either, so a
// static scene's motion vectors are the same bits under both.
// GBUFFER_MOTION_IGNORED (ignored) zeroes them, keeping them valid: a
// reprojection bug on purpose.
#version 460
#extension GL_GOOGLE_include_directive : require
// Bevy rasterises its G-buffer with bevy_pbr, which decodes normal maps as
// glTF says (v0.19.0:bevy_pbr/src/render/pbr_functions.wgsl:200, Nt * 2 - 1); only Solari's
// ray hits read the texel itself (textures.normal_map_decode raw, #24880).
// So here raw means signed; none still drops the maps.
#if defined(NORMAL_MAP_DECODE) && NORMAL_MAP_DECODE == 1
#undef NORMAL_MAP_DECODE
#define NORMAL_MAP_DECODE 2
#endif
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"
#include "gpu/shaders/gbuffer.h"
#include "core/clusters/cluster_ids.h"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_VISIBILITY) readonly buffer Visibility { uvec2 visibility[]; };
layout(std430, set = 0, binding = BINDING_DEPTH) readonly buffer Depth { float depth[]; };
layout(std430, set = 0, binding = BINDING_GBUFFER) writeonly buffer GBuffer { GBufferTexel gbuffer[]; };
layout(std430, set = 0, binding = BINDING_CLUSTER_TABLE) readonly buffer ClusterTable { uint cluster_table[]; };
#ifdef GBUFFER_MOTION_OBJECT
layout(std430, set = 0, binding = BINDING_PREVIOUS_TRANSFORMS) readonly buffer PreviousTransforms {
  mat4 previous_object_to_world[];
};
#endif

// (instance, primitive) named by a packed ID; false if it names no drawn triangle.
bool decode_visibility(uint packed, out uint instance, out uint primitive) {
  uint id = cluster_unpack_id(packed, cluster_table[CT_CLUSTER_BITS], cluster_table[CT_TRIANGLE_BITS]);
  uint tri = cluster_unpack_triangle(packed, cluster_table[CT_TRIANGLE_BITS]);
  uint records = cluster_table[CT_INSTANCES];
  uint lo = 0u, hi = cluster_table[CT_INSTANCE_COUNT];
  if (hi == 0u) return false;
  while (hi - lo > 1u) {  // the last instance whose first ID is <= id
    uint mid = (lo + hi) / 2u;
    if (cluster_table[records + 4u * mid] <= id) lo = mid; else hi = mid;
  }
  uint first = cluster_table[records + 4u * lo];
  uint local = id - first;
  if (id < first || local >= cluster_table[records + 4u * lo + 1u] || local >= cluster_table[records + 4u * lo + 3u])
    return false;
  uint cluster = cluster_table[records + 4u * lo + 2u] + local;
  primitive = cluster_table[cluster_table[CT_CLUSTERS] + cluster * cluster_table[CT_MAX_TRIANGLES] + tri];
  instance = lo;
  return primitive != CLUSTER_NO_PRIMITIVE;
}

// Barycentrics (u, v) of the ray's intersection with triangle (p0, p1, p2)
// (Möller–Trumbore without the range tests: the hit is known).
vec2 ray_barycentrics(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2) {
  vec3 e1 = p1 - p0;
  vec3 e2 = p2 - p0;
  vec3 pv = cross(d, e2);
  float det = dot(e1, pv);
  if (abs(det) < 1e-30) return vec2(1.0 / 3.0);
  float inv = 1.0 / det;
  vec3 tv = o - p0;
  vec3 qv = cross(tv, e1);
  return vec2(dot(tv, pv) * inv, dot(d, qv) * inv);
}

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;

  GBufferTexel g;
  g.position_depth = vec4(0.0);
  g.geometric_normal = vec4(0.0);
  g.shading_normal = vec4(0.0);
  g.base_color_metallic = vec4(0.0);
  g.emissive_roughness = vec4(0.0);
  g.motion_reflectance = vec4(0.0);

  uint instance, primitive;
  if (visibility[index].x != VISIBILITY_MISS && decode_visibility(visibility[index].x, instance, primitive)) {
    vec3 origin = vec3(frame.camera.position);
    vec3 dir = camera_ray_direction(frame.camera, pixel, resolution);
    GpuInstance inst = scene_instance(instance);
    uint base = inst.first_index + 3u * primitive;
    vec4 l0 = scene_vertex(inst.first_vertex + scene_index(base)).position;
    vec4 l1 = scene_vertex(inst.first_vertex + scene_index(base + 1u)).position;
    vec4 l2 = scene_vertex(inst.first_vertex + scene_index(base + 2u)).position;
    vec3 p0 = vec3(inst.object_to_world * l0);
    vec3 p1 = vec3(inst.object_to_world * l1);
    vec3 p2 = vec3(inst.object_to_world * l2);
    vec2 bary = ray_barycentrics(origin, dir, p0, p1, p2);
    SurfacePoint s = surface_at(instance, primitive, bary);
    GpuMaterial m = scene_material(s.material);

    g.position_depth = vec4(s.position, depth[index]);
    g.geometric_normal = vec4(s.geometric_normal, 1.0);
    g.shading_normal = vec4(s.shading_normal, m.reflectance.y);  // w: the material model (gbuffer.h)
    g.base_color_metallic = s.base_color_metallic;
    g.emissive_roughness = vec4(s.emissive, s.perceptual_roughness);
    vec3 previous_position = s.position;
#ifdef GBUFFER_MOTION_OBJECT
    mat4 previous_transform = previous_object_to_world[instance];
    if (previous_transform != inst.object_to_world) {
      vec4 local = (1.0 - bary.x - bary.y) * l0 + bary.x * l1 + bary.y * l2;
      previous_position = vec3(previous_transform * vec4(vec3(local), 1.0));
    }
#endif
    vec2 previous;
    bool valid = camera_project(frame.previous_camera, previous_position, resolution, previous);
    vec2 motion = valid ? previous - (vec2(pixel) + vec2(0.5)) : vec2(0.0);
#ifdef GBUFFER_MOTION_IGNORED
    motion = vec2(0.0);  // the profile's temporal.motion_vectors ignored: a reprojection bug
#endif
    g.motion_reflectance = vec4(motion, valid ? 1.0 : 0.0, m.reflectance.x);
  }
  gbuffer[index] = g;
}
