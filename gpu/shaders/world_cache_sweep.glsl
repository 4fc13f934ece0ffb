// What the full-table sweeps share (decay, compaction, statistics): a
// workgroup of WORLD_CACHE_CELL_GROUP invocations walks one compaction block
// of WORLD_CACHE_SCAN_BLOCK cells, each invocation WORLD_CACHE_SWEEP_CELLS
// adjacent cells, read four at a time through uvec4 views of the cache's
// per-cell words. lavapipe loads a lane's 16 bytes for what it pays for 4,
// and four dead cells are one test; on GPUs the lanes' loads stay contiguous.
// A pass that writes a buffer reads and writes it through one view (these or
// world_cache_common.glsl's), so no access depends on how the two alias.
// Include after world_cache_common.glsl.

layout(std430, set = 0, binding = BINDING_WC_CHECKSUMS) buffer WcChecksums4 { uvec4 wc_checksums4[]; };
layout(std430, set = 0, binding = BINDING_WC_LIFE) buffer WcLife4 { uvec4 wc_life4[]; };
layout(std430, set = 0, binding = BINDING_WC_CLAIMS) buffer WcClaims4 { uvec4 wc_claims4[]; };

const uint SWEEP_QUADS = WORLD_CACHE_SWEEP_CELLS / 4u;  // uvec4 words per invocation

// The invocation's first cell: its block's first plus its run of SWEEP_CELLS.
uint sweep_first_cell() {
  return gl_WorkGroupID.x * WORLD_CACHE_SCAN_BLOCK + gl_LocalInvocationID.x * WORLD_CACHE_SWEEP_CELLS;
}

uint live_count(uvec4 life) {
  return uint(life.x != 0u) + uint(life.y != 0u) + uint(life.z != 0u) + uint(life.w != 0u);
}
