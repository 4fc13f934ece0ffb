// Primary visibility: one camera ray per pixel through the pixel centre (no
// AA jitter, docs/design.md §3), closest hit written to the visibility buffer and its
// t to depth. Each pixel is a uvec2:
//   x  the packed ID `cluster_id << triangle_bits | triangle` (docs/design.md §8,
//      core/clusters/cluster_ids.h): the hit primitive's LOD-0 cluster and its
//      place in it, offset by the instance's first ID. Only the low
//      cluster_bits survive, as in Bevy: past the limit the ID aliases.
//   y  the hit instance, written independently of x: the check channel the
//      cluster_ids check compares decoded IDs against.
// Both are VISIBILITY_MISS on a miss.
#version 460
#extension GL_GOOGLE_include_directive : require
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"
#include "core/clusters/cluster_ids.h"

layout(local_size_x = RAY_WORKGROUP_X, local_size_y = RAY_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_VISIBILITY) writeonly buffer Visibility { uvec2 visibility[]; };
layout(std430, set = 0, binding = BINDING_DEPTH) writeonly buffer Depth { float depth[]; };
layout(std430, set = 0, binding = BINDING_CLUSTER_TABLE) readonly buffer ClusterTable { uint cluster_table[]; };

void main() {
  uvec2 resolution = frame.resolution_frame.xy;
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, resolution))) return;
  uint index = pixel.y * resolution.x + pixel.x;

  vec3 dir = camera_ray_direction(frame.camera, pixel, resolution);
  Hit hit;
  if (trace_closest(vec3(frame.camera.position), dir, RAY_TMAX, hit)) {
    uint triangle = scene_instance(hit.instance).first_index / 3u + hit.primitive;
    uint where = cluster_table[cluster_table[CT_PRIMITIVES] + triangle];  // LOD-0 cluster << 8 | place
    uint first_id = cluster_table[cluster_table[CT_INSTANCES] + 4u * hit.instance];
    uint packed = cluster_pack(first_id + (where >> 8), where & 255u, cluster_table[CT_CLUSTER_BITS],
                               cluster_table[CT_TRIANGLE_BITS]);
    visibility[index] = uvec2(packed, hit.instance);
    depth[index] = hit.t;
  } else {
    visibility[index] = uvec2(VISIBILITY_MISS);
    depth[index] = 0.0;
  }
}
