// Light tiles (docs/design.md §3 step 4): LIGHT_TILE_COUNT tiles × LIGHT_TILE_SAMPLES
// light samples per DI chain, drawn uniformly (light, triangle, point; no
// scene heuristic), resolved and packed into 24 bytes (core/shared/light_tiles.h).
// One invocation per sample; y indexes the chain (independent random streams).
//
// Defines: LIGHT_TILE_COUNT, LIGHT_TILE_SAMPLES, LIGHT_TILE_EXPOSURE,
// LIGHT_TILE_LOG2_RADIANCE (1: rgb9e5(log2(L·e + 1)), 0: plain rgb9e5).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/scene_bindings.glsl"
#include "core/shared/light_tiles.h"
#include "core/shared/reservoir.h"
#include "core/shared/restir_di.h"
#include "gpu/shaders/di_bindings.h"
#include "core/shared/light_sampling.h"

layout(local_size_x = LIGHT_TILE_WORKGROUP) in;

layout(std430, set = 0, binding = BINDING_LIGHT_TILE_SAMPLES) writeonly buffer TileSamples { LightSample tile_samples[]; };
layout(std430, set = 0, binding = BINDING_LIGHT_TILE_PACKED) writeonly buffer TilePacked { PackedLightSample tile_packed[]; };

void main() {
  uint per_chain = uint(LIGHT_TILE_COUNT) * uint(LIGHT_TILE_SAMPLES);
  uint i = gl_GlobalInvocationID.x;
  uint chain = gl_GlobalInvocationID.y;
  if (i >= per_chain) return;
#if LIGHT_TILE_SCROLLING != 0
  // Bevy before #24670 (v0.19.0:realtime/presample_light_tiles.wgsl:16 with
  // node.rs:236): seed (tile + frame) · c + sample, so the pools scroll by
  // one tile a frame.
  uint tile = i / uint(LIGHT_TILE_SAMPLES);
  uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_LIGHT_TILES + chain,
                      (tile + frame.resolution_frame.z) * uint(LIGHT_TILE_SAMPLES) + i % uint(LIGHT_TILE_SAMPLES), 0u);
#else
  uint rng = rng_seed(frame.resolution_frame.w, RNG_DOMAIN_LIGHT_TILES + chain, i, frame.resolution_frame.z);
#endif
  LightSample s = generate_light_sample(rng);
  PackedLightSample p;
  p.position_x = 0.0;
  p.position_y = 0.0;
  p.position_z = 0.0;
  p.normal = 0u;
  p.radiance = 0u;
  p.inverse_pdf = 0.0;
  if (s.valid != 0u) p = pack_light_sample(resolve_light_sample(s), LIGHT_TILE_EXPOSURE, LIGHT_TILE_LOG2_RADIANCE != 0);
  tile_samples[chain * per_chain + i] = s;
  tile_packed[chain * per_chain + i] = p;
}
