// The world cache's maths (docs/design.md §3 step 5; seeds/solari-0.17-draft.md "World
// Cache", seeds/solari-0.18.md "World Cache Improvements"), shared by the GPU
// passes (gpu/shaders/world_cache_*.comp), the checks and the unit tests
// (host_device.h rules): hashing and checksums, LOD cell size, probing, the
// lifetime rules, the fixed (0.17) and adaptive (0.18) blends.
#ifndef GI_SHARED_WORLD_CACHE_H
#define GI_SHARED_WORLD_CACHE_H
#include "host_device.h"
#include "rng.h"
#include "sampling.h"

GI_SHADER_BEGIN

GI_CONST uint WORLD_CACHE_EMPTY_CELL = 0u;         // checksum of a free cell
GI_CONST uint WORLD_CACHE_NO_CLAIM = 0xFFFFFFFFu;  // claims[] of a cell nobody asked for this pass
// Random streams of the cache update (added to nothing: one chain).
GI_CONST uint RNG_DOMAIN_WORLD_CACHE_DI = 0x61C88647u;
GI_CONST uint RNG_DOMAIN_WORLD_CACHE_GI = 0x7FEB352Du;
GI_CONST uint RNG_DOMAIN_WORLD_CACHE_SOFT_CAP = 0x2C1B3C6Du;  // which cells this frame's update skips (0.19)
GI_CONST uint RNG_DOMAIN_WORLD_CACHE_VIEW = 0x297A2D39u;      // the cache view's jitter and LOD draws (0.19)
// Fixed point of the per-frame radiance sum (stats): 1/1024 of a unit of
// luminance per cell, summed in 64 bits as two uints, so the sum is exact and
// independent of the order the atomics land in.
GI_CONST float WORLD_CACHE_STATS_SCALE = 1024.0f;

// Inigo Quilez's integer hash ("iqint1" in Jarzynski & Olano, JCGT 2020), the
// checksum hash Solari chains.
GI_FN uint iqint_hash(uint v) {
  uint n = (v << 13u) ^ v;
  return n * (n * n * 15731u + 789221u) + 1376312589u;
}

// Solari's get_cell_size: base · 2^floor(log2(1 + d / lod_scale)).
GI_FN float world_cache_cell_size(vec3 position, vec3 view_position, float base, float lod_scale) {
  float d = distance(view_position, position) / lod_scale;
  return base * exp2(floor(log2(1.0f + d)));
}

// Solari 0.19's get_cell_size (v0.19.0:realtime/world_cache_query.wgsl:98-104):
// the LOD's fractional part picks the next LOD with probability fract³, so
// cells change size gradually with distance instead of at one radius. u is
// uniform in [0, 1).
GI_FN float world_cache_cell_size_stochastic(vec3 position, vec3 view_position, float base, float lod_scale,
                                             float u) {
  float lod_f = log2(1.0f + distance(view_position, position) / lod_scale);
  float f = fract(lod_f);
  float lod = floor(lod_f) + (u < f * f * f ? 1.0f : 0.0f);
  return base * exp2(lod);
}

// Solari 0.19's query jitter (v0.19.0:realtime/world_cache_query.wgsl:54-61,
// after Clabault's jitter_world_position_tangent_plane): the query point moves
// by up to half a cell along each tangent of the normal, which blurs the
// cache's grid. u uniform in [0, 1)². orthonormal_basis is Duff et al.'s, as
// Bevy's orthonormalize.
GI_FN vec3 world_cache_jitter(vec3 position, vec3 normal, float cell_size, vec2 u) {
  vec2 offset = (u * 2.0f - 1.0f) * cell_size * 0.5f;
  return position + to_world(vec3(offset.x, offset.y, 0.0f), normal);
}

GI_FN uvec3 world_cache_quantize_position(vec3 position, float cell_size) {
  return floatBitsToUint(floor(position / cell_size + 0.0001f));
}

// The normal's part of the key: floor(n · scale), scale 1 up to 0.18 (one of
// a few octants), 2 in 0.19 (half-unit steps: finer, so walls at an angle and
// the two sides of a thin slab share fewer cells;
// v0.19.0:realtime/world_cache_query.wgsl:111).
GI_FN uvec3 world_cache_quantize_normal(vec3 normal, float scale) {
  return floatBitsToUint(floor(normal * scale + 0.0001f));
}

// Solari 0.19's soft cap on the cells updated a frame
// (v0.19.0:realtime/world_cache_update.wgsl:37,52,71): with more than `cap`
// active cells, each is updated with probability cap / active, the same
// draw in the DI, GI and blend passes. cap 0: every cell (0.17, 0.18). u is
// the cell's draw for this frame, uniform in [0, 1).
GI_FN bool world_cache_update_skipped(uint cap, uint active_cells, float u) {
  return cap != 0u && u >= float(cap) / float(active_cells);
}

// Table index: chained pcg_hash, masked to the (power-of-two) table.
GI_FN uint world_cache_key(uvec3 qp, uvec3 qn, uint cells) {
  uint k = pcg_hash(qp.x);
  k = pcg_hash(k + qp.y);
  k = pcg_hash(k + qp.z);
  k = pcg_hash(k + qn.x);
  k = pcg_hash(k + qn.y);
  k = pcg_hash(k + qn.z);
  return k & (cells - 1u);
}

// Collision detection: chained iqint_hash, never WORLD_CACHE_EMPTY_CELL.
GI_FN uint world_cache_checksum(uvec3 qp, uvec3 qn) {
  uint k = iqint_hash(qp.x);
  k = iqint_hash(k + qp.y);
  k = iqint_hash(k + qp.z);
  k = iqint_hash(k + qn.x);
  k = iqint_hash(k + qn.y);
  k = iqint_hash(k + qn.z);
  return k == WORLD_CACHE_EMPTY_CELL ? 1u : k;
}

// The next slot after a collision: key + 1 (0.18) or pcg_hash(key) (0.17).
GI_FN uint world_cache_next_key(uint key, uint cells, bool linear_probing) {
  return (linear_probing ? key + 1u : pcg_hash(key)) & (cells - 1u);
}

// The life a query gives the cell it finds (applied with atomicMax; a store of
// the full lifetime is the same thing, since no life exceeds it):
// pixel-rooted queries (GI, specular, the cache view) the full lifetime;
// cache-to-cache queries the querying cell's current life (0.18), or the full
// lifetime (0.17: cells kept each other alive forever).
GI_FN uint world_cache_query_life(bool pixel_rooted, uint querier_life, uint lifetime, bool cache_to_cache_full) {
  return (pixel_rooted || cache_to_cache_full) ? lifetime : min(querier_life, lifetime);
}

// Decay: one frame less; a cell reaching 0 is cleared (by the caller).
GI_FN uint world_cache_decayed_life(uint life) { return life > 0u ? life - 1u : 0u; }

// The cache_lifetime invariant (docs/design.md §6) for a live cell at `frame` whose
// last pixel-rooted refresh, propagated with max along cache-to-cache
// queries, was `root_frame`.
GI_FN uint world_cache_age(uint frame, uint root_frame) { return frame >= root_frame ? frame - root_frame : 0u; }
GI_FN bool world_cache_age_ok(uint frame, uint root_frame, uint lifetime) {
  return world_cache_age(frame, root_frame) <= lifetime + 1u;
}

struct WorldCacheBlend {
  vec4 radiance;          // rgb irradiance, a sample count
  float luminance_delta;  // 0.18's smoothed frame-to-frame luminance change
};

// 0.17: rgb = mix(old, new, 1/min(old.a + 1, max_samples)); no delta.
GI_FN WorldCacheBlend world_cache_blend_fixed(vec4 old_radiance, vec3 new_radiance, float max_samples) {
  float n = min(old_radiance.w + 1.0f, max_samples);
  WorldCacheBlend b;
  b.radiance = vec4(mix(vec3(old_radiance), new_radiance, 1.0f / n), n);
  b.luminance_delta = 0.0f;
  return b;
}

// 0.18 (Guillaume Boissé's adaptive blend, seeds/solari-0.18.md "Cache Lag"):
// the sample cap falls towards 1 as the smoothed luminance change grows
// relative to the cell's luminance. exponent 1/8, delta_blend 1/8 in 0.18.
GI_FN WorldCacheBlend world_cache_blend_adaptive(vec4 old_radiance, float luminance_delta, vec3 new_radiance,
                                                 float max_samples, float exponent, float delta_blend) {
  float n = min(old_radiance.w + 1.0f, max_samples);
  float alpha = abs(luminance_delta) / max(luminance(vec3(old_radiance)), 0.001f);
  float n_max = mix(max_samples, 1.0f, pow(saturate(alpha), exponent));
  vec3 rgb = mix(vec3(old_radiance), new_radiance, 1.0f / min(n, n_max));
  WorldCacheBlend b;
  b.radiance = vec4(rgb, n);
  b.luminance_delta = mix(luminance_delta, luminance(rgb) - luminance(vec3(old_radiance)), delta_blend);
  return b;
}

// One cell's geometry: the query point that created it (position, normal
// facing the side it was seen from).
struct WorldCacheGeometry {
  vec4 position;  // xyz, w unused
  vec4 normal;    // xyz unit, w unused
};

// A query that found an empty slot and, when it asked, held the lowest claim
// there. The commit pass writes the record whose query_id still holds the
// claim: the same winner on every run and thread count (Solari's CAS race
// made the first writer win). Scalars only: std430 and C++ agree (36 bytes).
struct WorldCachePending {
  uint slot;
  uint query_id;   // pixel index (pixel-rooted) or querying cell (cache-to-cache): unique within a pass
  uint checksum;
  uint life;
  uint root_frame;
  float position_x;
  float position_y;
  float position_z;
  uint normal;     // octahedral (packing.h)
};

// Counters and indirect dispatches (VkDispatchIndirectCommand at offsets 0,
// 16, 32): the active list of this frame's update, and the pending insertions
// of the two query passes (cache-to-cache, pixel-rooted).
struct WorldCacheCounters {
  uvec4 active_args;    // xyz groups, w active cells
  uvec4 gi_pending;     // xyz groups, w records
  uvec4 pixel_pending;  // xyz groups, w records
};

// What the stats pass counts at the end of a frame (integer atomics only).
struct WorldCacheStats {
  uint live_cells;            // life > 0
  uint sampled_cells;         // live with at least one blended sample
  uint radiance_sum_lo;       // Σ luminance · WORLD_CACHE_STATS_SCALE over sampled cells, 64-bit
  uint radiance_sum_hi;
  uint over_age_cells;        // live with frame − root_frame > lifetime + 1 (root frame instrumentation)
  uint oldest_age;            // max frame − root_frame over live cells
  uint life_out_of_range;     // life > lifetime
  uint dead_not_empty;        // life == 0 with a checksum
  uint nonfinite_cells;       // inf/NaN radiance
  uint updated_cells;         // active cells this frame's update blended (fewer under 0.19's soft cap)
  uint pad1;
  uint pad2;
};

GI_CONST uint WORLD_CACHE_SCAN_BLOCK = 1024u;  // cells per block of the two-level compaction
GI_CONST uint WORLD_CACHE_SCAN_THREADS = 256u; // 4 cells per thread
GI_CONST uint WORLD_CACHE_CELL_GROUP = 64u;    // per-cell and per-record passes (docs/design.md §3: 64 for ray passes)
// The full-table sweeps (decay, compaction, statistics) give each invocation
// this many adjacent cells, so a workgroup walks one scan block
// (gpu/shaders/world_cache_sweep.glsl): fewer invocations for lavapipe to
// start (each cell's work is a few loads), the same result per cell.
GI_CONST uint WORLD_CACHE_SWEEP_CELLS = 16u;

GI_SHADER_END

#endif
