// Random numbers for the GPU pipeline and the Embree reference.
// PCG hash (Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020)
// seeds a per-sample state; the state then advances as a PCG-RXS-M-XS stream.
// Seeds are built from (seed, pixel, sample, domain) only, never from thread
// ids, so every image is bit-reproducible at any thread count.
#ifndef GI_SHARED_RNG_H
#define GI_SHARED_RNG_H
#include "host_device.h"

GI_SHADER_BEGIN

GI_FN uint pcg_hash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Distinct streams for the renderers, so the GPU and the Embree reference
// never draw the same numbers (their noise must be independent to compare).
GI_CONST uint RNG_DOMAIN_GPU_REFERENCE = 0x9E3779B9u;
GI_CONST uint RNG_DOMAIN_EMBREE = 0x85EBCA6Bu;

GI_FN uint rng_seed(uint seed, uint domain, uint pixel_index, uint sample_index) {
  return pcg_hash(pixel_index ^ pcg_hash(sample_index ^ pcg_hash(seed ^ domain)));
}

GI_FN uint rng_next_uint(INOUT(uint) state) {
  state = state * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Uniform in [0, 1): the top 24 bits, exactly representable in a float.
GI_FN float rng_next_float(INOUT(uint) state) {
  return float(rng_next_uint(state) >> 8u) * (1.0f / 16777216.0f);
}

GI_FN vec2 rng_next_vec2(INOUT(uint) state) {
  vec2 r;
  r.x = rng_next_float(state);
  r.y = rng_next_float(state);
  return r;
}

GI_SHADER_END

#endif
