// World cache update, indirect light (DESIGN §3 step 5; Solari's
// sample_irradiance, 2nd ray): per active cell a cosine-distributed ray of at
// most WORLD_CACHE_GI_TMAX; at a hit, the hit's diffuse colour times the
// cache there (a cache-to-cache query: life by the profile's rule, root frame
// passed on). Irradiance estimate: π · (ρ/π) · E_hit = ρ · E_hit. Emission at
// the hit is left out: the direct sample owns the lights.
#version 460
#extension GL_GOOGLE_include_directive : require
#define SCENE_BINDINGS_NO_INTEGRATOR
#include "gpu/shaders/scene_bindings.glsl"
#include "core/shared/path_integrator.h"
#include "gpu/shaders/world_cache_common.glsl"
#include "gpu/shaders/world_cache_query.glsl"

layout(local_size_x = WORLD_CACHE_CELL_GROUP) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= wc_counters.active_args.w) return;
  uint cell = wc_active[i];
  uvec2 state = wc_active_state[i];  // (life, root frame) before this frame's queries
  vec3 p = wc_geometry[cell].position.xyz;
  vec3 n = wc_geometry[cell].normal.xyz;
  uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_WORLD_CACHE_GI, wc_checksums[cell], frame.resolution_frame.z);
  vec3 dir = to_world(sample_cosine_hemisphere(rng_next_vec2(rng)), n);
  Hit hit;
  vec3 irradiance = vec3(0.0);
  if (trace_closest(offset_ray_origin(p, n), dir, float(WORLD_CACHE_GI_TMAX), hit)) {
    SurfacePoint s = surface_at_hit(hit);
    vec3 hit_position = s.position;
    vec3 hit_normal = dot(s.geometric_normal, dir) > 0.0 ? -s.geometric_normal : s.geometric_normal;
    GpuMaterial m = scene_material(s.material);
    vec3 diffuse = m.base_color_metallic.rgb * (1.0 - m.base_color_metallic.a);
    uint life = world_cache_query_life(false, state.x, uint(WORLD_CACHE_LIFETIME), WORLD_CACHE_C2C_FULL != 0);
    irradiance = diffuse * world_cache_query(hit_position, hit_normal, life, state.y, cell, 0u);
  }
  wc_new_radiance[i] += vec4(irradiance, 0.0);
}
