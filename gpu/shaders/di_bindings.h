// Descriptor bindings and push constants of the realtime DI passes (light
// tiles, ReSTIR DI), shared by C++ and GLSL (host_device.h rules). Numbers
// 40-49 are reserved here so that other passes' bindings (bindings.h) never
// collide with them; the G-buffer keeps its number from bindings.h.
#ifndef GI_GPU_SHADERS_DI_BINDINGS_H
#define GI_GPU_SHADERS_DI_BINDINGS_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

GI_CONST uint BINDING_LIGHT_TILE_SAMPLES = 40u;   // LightSample[chains · tiles · samples]
GI_CONST uint BINDING_LIGHT_TILE_PACKED = 41u;    // PackedLightSample[chains · tiles · samples]
GI_CONST uint BINDING_DI_RESERVOIRS_STORED = 42u; // DiReservoir[chains · pixels]: last frame's, for temporal reuse
GI_CONST uint BINDING_DI_RESERVOIRS_MID = 43u;    // DiReservoir[chains · pixels]: initial + temporal, for spatial reuse
GI_CONST uint BINDING_DI_SURFACES = 44u;          // DiSurface[pixels]: last frame's surfaces
GI_CONST uint BINDING_DI_LIGHT_TRANSLATION = 45u; // uint[previous light count]: id this frame or LIGHT_ID_GONE
GI_CONST uint BINDING_DI_OUTPUT = 46u;            // vec4[chains · pixels]: this frame's DI (w 1 on a hit)
GI_CONST uint BINDING_DI_ACCUMULATION = 47u;      // vec4[chains · pixels]: rgb sum over the window, w frames

struct DiPushConstants {
  uint chain_count;
  uint previous_light_count;  // entries of the translation table
  uint history_valid;         // 0 on the first frame: no temporal reuse
  uint accumulate;            // 1: add this frame to the accumulation
};

// light_tiles.comp: one invocation per tile sample, 64 a workgroup.
GI_CONST uint LIGHT_TILE_WORKGROUP = 64u;

GI_SHADER_END

#endif
