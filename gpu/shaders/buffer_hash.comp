// The harness's buffer hash (core/shared/word_hash.h) of any buffer, found by
// its device address: one invocation per chunk of words, the chunks' lane
// hashes added with integer atomics (order-free, so the sums are the CPU's),
// first within the workgroup, then once per workgroup into the slot.
// The host finishes the hash (word_hash_finish) from the slot's two sums.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
#include "core/shared/word_hash.h"
#include "gpu/shaders/frame_output_bindings.h"

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Words { uint w[]; };

layout(std430, set = 0, binding = BINDING_HASH_SUMS) buffer Sums { uvec2 sums[]; };

layout(push_constant) uniform Push {
  uvec2 address;  // of the first word
  uint words;
  uint slot;
} pc;

layout(local_size_x = BUFFER_HASH_GROUP) in;

shared uint group_sum_x, group_sum_y;

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    group_sum_x = 0u;
    group_sum_y = 0u;
  }
  barrier();
  const uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  const uint chunk = group * BUFFER_HASH_GROUP + gl_LocalInvocationIndex;
  const uint chunks = (pc.words + WORD_HASH_CHUNK - 1u) / WORD_HASH_CHUNK;
  if (chunk < chunks) {
    Words words = Words(pc.address);
    const uint first = chunk * WORD_HASH_CHUNK;
    const uint n = min(WORD_HASH_CHUNK, pc.words - first);
    uvec2 h = word_hash_chunk_begin(chunk);
    for (uint i = 0u; i < n; ++i) h = word_hash_chunk_add(h, words.w[first + i]);
    h = word_hash_chunk_end(h, n);
    atomicAdd(group_sum_x, h.x);
    atomicAdd(group_sum_y, h.y);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    atomicAdd(sums[pc.slot].x, group_sum_x);
    atomicAdd(sums[pc.slot].y, group_sum_y);
  }
}
