// Descriptor bindings and push constants of the world-cache passes, shared by
// C++ and GLSL (host_device.h rules). Numbers 50-63 are the cache's. Every
// cache pass sees the same table (gpu/passes/world_cache.cpp binds all of it),
// so a buffer has one number in every pass.
#ifndef GI_GPU_SHADERS_WORLD_CACHE_BINDINGS_H
#define GI_GPU_SHADERS_WORLD_CACHE_BINDINGS_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

// Persistent (listed by WorldCache::list_state).
GI_CONST uint BINDING_WC_CHECKSUMS = 50u;    // uint[cells]: WORLD_CACHE_EMPTY_CELL or the checksum
GI_CONST uint BINDING_WC_LIFE = 51u;         // uint[cells]: frames left
GI_CONST uint BINDING_WC_RADIANCE = 52u;     // vec4[cells]: rgb irradiance, a sample count
GI_CONST uint BINDING_WC_DELTA = 53u;        // float[cells]: smoothed luminance change (adaptive blend)
GI_CONST uint BINDING_WC_GEOMETRY = 54u;     // WorldCacheGeometry[cells]
GI_CONST uint BINDING_WC_ROOT_FRAME = 55u;   // uint[cells]: last pixel-rooted refresh (max-propagated)
// Per frame.
GI_CONST uint BINDING_WC_CLAIMS = 56u;       // uint[cells]: lowest query id asking for the empty slot this pass
GI_CONST uint BINDING_WC_ACTIVE = 57u;       // uint[cells]: active cell indices, ascending
GI_CONST uint BINDING_WC_ACTIVE_STATE = 58u; // uvec2[cells]: per active cell, (life, root frame) before any query
GI_CONST uint BINDING_WC_NEW_RADIANCE = 59u; // vec4[cells]: per active cell, this frame's sample
GI_CONST uint BINDING_WC_BLOCK_SUMS = 60u;   // uint[cells / WORLD_CACHE_SCAN_BLOCK]: live cells, then offsets
GI_CONST uint BINDING_WC_COUNTERS = 61u;     // WorldCacheCounters (also the indirect dispatch arguments)
GI_CONST uint BINDING_WC_PENDING = 62u;      // WorldCachePending[max(pixels, cells)]
GI_CONST uint BINDING_WC_STATS = 63u;        // WorldCacheStats
GI_CONST uint BINDING_WC_VIEW = 64u;         // vec4[pixels]: the cache view (irradiance at the primary surface)

struct WorldCachePush {
  uint pass_kind;  // which pending list a commit/args pass works on: 0 cache-to-cache, 1 pixel-rooted
  uint pad0;
  uint pad1;
  uint pad2;
};

GI_SHADER_END

#endif
