// The reusable world-cache query (docs/design.md §3 step 5), for any pass that looks
// the cache up: the cache view now, ReSTIR GI and specular GI later
// (pixel-rooted), the cache's own GI samples (cache-to-cache). Include after
// scene_bindings.glsl and world_cache_common.glsl.

// Appends an insertion request to the pending list of this pass (0
// cache-to-cache, 1 pixel-rooted).
void world_cache_request_insert(uint list, uint slot, uint query_id, uint checksum, uint life, uint root_frame,
                                vec3 position, vec3 normal) {
  uint i = list == 0u ? atomicAdd(wc_counters.gi_pending.w, 1u) : atomicAdd(wc_counters.pixel_pending.w, 1u);
  if (i >= uint(WORLD_CACHE_PENDING_CAPACITY)) return;  // cannot happen: one record per query at most
  WorldCachePending p;
  p.slot = slot;
  p.query_id = query_id;
  p.checksum = checksum;
  p.life = life;
  p.root_frame = root_frame;
  p.position_x = position.x;
  p.position_y = position.y;
  p.position_z = position.z;
  p.normal = pack_unit_vector(normal);
  wc_pending[i] = p;
}

// The cell size where a query lands: floor LOD (0.17, 0.18) or 0.19's
// stochastic one, which draws from rng.
float world_cache_query_cell_size(vec3 position, inout uint rng) {
#if WORLD_CACHE_STOCHASTIC_LOD != 0
  return world_cache_cell_size_stochastic(position, frame.camera.position.xyz, float(WORLD_CACHE_CELL_SIZE_BASE),
                                          float(WORLD_CACHE_LOD_SCALE), rng_next_float(rng));
#else
  return world_cache_cell_size(position, frame.camera.position.xyz, float(WORLD_CACHE_CELL_SIZE_BASE),
                               float(WORLD_CACHE_LOD_SCALE));
#endif
}

// Solari's query_world_cache with deterministic insertion. Returns the cell's
// irradiance from last frame's blend, or 0 for a new or unplaceable cell.
//   normal: the surface normal facing the querier.
//   ray_t:  the length of the ray that found `position`; with
//           first_bounce (ReSTIR GI's initial sample) and
//           WORLD_CACHE_LEAK_RULE, a ray shorter than its cell queries a base
//           cell (0.19's WORLD_CACHE_FIRST_BOUNCE_LIGHT_LEAK_PREVENTION,
//           v0.19.0:realtime/world_cache_query.wgsl:47-52, node.rs:564).
//   life:   world_cache_query_life(...) — the full lifetime for pixel-rooted
//           queries, the querier's life for 0.18 cache-to-cache queries.
//   root_frame: this frame (pixel-rooted) or the querier's root frame.
//   query_id: unique among this pass's queries (pixel index / querying cell).
//   list: 0 cache-to-cache pass, 1 pixel-rooted pass.
//   rng:  the querier's stream; drawn from only by 0.19's stochastic LOD and
//         jitter, in Bevy's order (LOD, jitter, LOD again), so 0.17 and 0.18
//         leave the querier's numbers as they were.
// A found cell's life and root frame are raised with atomicMax (order-free);
// checksums, radiance and geometry are only read here: inserts wait for the
// commit pass, which writes the lowest query id's record per slot. A new
// cell's geometry is the (jittered) query point, as Bevy stores it.
vec3 world_cache_query(vec3 position, vec3 normal, float ray_t, bool first_bounce, uint life, uint root_frame,
                       uint query_id, uint list, inout uint rng) {
  float cell_size = world_cache_query_cell_size(position, rng);
#if WORLD_CACHE_LEAK_RULE != 0
  if (first_bounce && ray_t < cell_size) cell_size = float(WORLD_CACHE_CELL_SIZE_BASE);
#endif
#if WORLD_CACHE_JITTER != 0
  position = world_cache_jitter(position, normal, cell_size, rng_next_vec2(rng));
#if WORLD_CACHE_JITTER_LOD_REDRAWN != 0
  cell_size = world_cache_query_cell_size(position, rng);
#endif
#endif
  uvec3 qp = world_cache_quantize_position(position, cell_size);
  uvec3 qn = world_cache_quantize_normal(normal, float(WORLD_CACHE_NORMAL_KEY_SCALE));
  uint key = world_cache_key(qp, qn, uint(WORLD_CACHE_CELLS));
  uint checksum = world_cache_checksum(qp, qn);
  for (uint i = 0u; i < uint(WORLD_CACHE_MAX_PROBE_STEPS); ++i) {
    uint existing = wc_checksums[key];
    if (existing == checksum) {
      atomicMax(wc_life[key], life);
#ifdef WORLD_CACHE_ROOT_FRAME
      atomicMax(wc_root_frame[key], root_frame);
#endif
      return wc_radiance[key].rgb;
    }
    if (existing == WORLD_CACHE_EMPTY_CELL) {
      // Ask only while this query could still win (a lower id already holds it otherwise).
      if (atomicMin(wc_claims[key], query_id) > query_id)
        world_cache_request_insert(list, key, query_id, checksum, life, root_frame, position, normal);
      return vec3(0.0);
    }
    key = world_cache_next_key(key, uint(WORLD_CACHE_CELLS), WORLD_CACHE_LINEAR_PROBING != 0);
  }
  return vec3(0.0);
}
