// What every world-cache pass shares: the cache's buffers and the reusable
// query (docs/design.md §3 step 5); also included by the GI passes that query the
// cache (GI_HIT_RADIANCE 2), with the same defines. Include after #version (and after
// scene_bindings.glsl in passes that trace). Settings come as defines
// (gpu/passes/world_cache.cpp, WorldCacheSettings::defines):
//   WORLD_CACHE_CELLS (power of two), WORLD_CACHE_LIFETIME, WORLD_CACHE_MAX_PROBE_STEPS,
//   WORLD_CACHE_LINEAR_PROBING (1 key + 1, 0 re-hash), WORLD_CACHE_CELL_SIZE_BASE,
//   WORLD_CACHE_LOD_SCALE, WORLD_CACHE_C2C_FULL (1: 0.17 lifetime rule),
//   WORLD_CACHE_ADAPTIVE (1: 0.18 blend), WORLD_CACHE_MAX_SAMPLES, WORLD_CACHE_ADAPTIVE_EXPONENT,
//   WORLD_CACHE_DELTA_BLEND, WORLD_CACHE_DI_SAMPLES, WORLD_CACHE_GI_TMAX,
//   WORLD_CACHE_LIGHT_EXPOSURE, WORLD_CACHE_LOG2_RADIANCE, WORLD_CACHE_PENDING_CAPACITY,
//   WORLD_CACHE_STOCHASTIC_LOD, WORLD_CACHE_JITTER, WORLD_CACHE_NORMAL_KEY_SCALE,
//   WORLD_CACHE_LEAK_RULE, WORLD_CACHE_UPDATE_SOFT_CAP (0.19's query and update),
//   WORLD_CACHE_JITTER_LOD_REDRAWN (1: the cell size drawn again at the
//   jittered point, as 0.18's opt-in jitter and 0.19; 0: Bevy #21953's bug),
//   WORLD_CACHE_UPDATE_GROUP (workgroup width of the per-active-cell passes:
//   sample_di, sample_gi, blend; world_cache.workgroup_size),
//   WORLD_CACHE_ROOT_FRAME (defined only with the cache_lifetime check: root-frame instrumentation).
#extension GL_GOOGLE_include_directive : require
#include "core/shared/world_cache.h"
#include "core/shared/packing.h"
#include "gpu/shaders/world_cache_bindings.h"

layout(std430, set = 0, binding = BINDING_WC_CHECKSUMS) buffer WcChecksums { uint wc_checksums[]; };
layout(std430, set = 0, binding = BINDING_WC_LIFE) buffer WcLife { uint wc_life[]; };
layout(std430, set = 0, binding = BINDING_WC_RADIANCE) buffer WcRadiance { vec4 wc_radiance[]; };
layout(std430, set = 0, binding = BINDING_WC_DELTA) buffer WcDelta { float wc_delta[]; };
layout(std430, set = 0, binding = BINDING_WC_GEOMETRY) buffer WcGeometry { WorldCacheGeometry wc_geometry[]; };
layout(std430, set = 0, binding = BINDING_WC_ROOT_FRAME) buffer WcRoot { uint wc_root_frame[]; };
layout(std430, set = 0, binding = BINDING_WC_CLAIMS) buffer WcClaims { uint wc_claims[]; };
layout(std430, set = 0, binding = BINDING_WC_ACTIVE) buffer WcActive { uint wc_active[]; };
layout(std430, set = 0, binding = BINDING_WC_ACTIVE_STATE) buffer WcActiveState { uvec2 wc_active_state[]; };
layout(std430, set = 0, binding = BINDING_WC_NEW_RADIANCE) buffer WcNew { vec4 wc_new_radiance[]; };
layout(std430, set = 0, binding = BINDING_WC_BLOCK_SUMS) buffer WcBlocks { uint wc_block_sums[]; };
layout(std430, set = 0, binding = BINDING_WC_COUNTERS) buffer WcCounters { WorldCacheCounters wc_counters; };
layout(std430, set = 0, binding = BINDING_WC_PENDING) buffer WcPending { WorldCachePending wc_pending[]; };
layout(std430, set = 0, binding = BINDING_WC_STATS) buffer WcStats { WorldCacheStats wc_stats; };
layout(std430, set = 0, binding = BINDING_WC_VIEW) buffer WcView { vec4 wc_view[]; };

// No push-constant block here: passes that include this file from outside
// the cache (ReSTIR GI, specular GI) have their own. The two cache passes
// that read WorldCachePush (pending_args, commit) declare it themselves.

