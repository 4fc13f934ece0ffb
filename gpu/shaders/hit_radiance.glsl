// Secondary hits on the GPU: the shared path logic (core/shared/secondary_hit.h,
// which documents the HIT_* defines the includer sets) ending, for
// HIT_RADIANCE 2, in this pass's world-cache query.
//
// Include after scene_bindings.glsl with the path integrator (and, for
// HIT_RADIANCE 2, world_cache_common.glsl and world_cache_query.glsl).

#include "core/shared/specular.h"
#include "core/shared/secondary_hit.h"

#if HIT_RADIANCE == 2
vec3 hit_cache_irradiance(vec3 position, vec3 ng, float ray_t, CacheQuery q, inout uint rng) {
  return world_cache_query(position, ng, ray_t, q.first_bounce != 0u, q.life, q.root_frame, q.id, q.list, rng);
}

float hit_cache_cell_size(vec3 position, uint rng) {
  return world_cache_query_cell_size(position, rng);
}
#endif
