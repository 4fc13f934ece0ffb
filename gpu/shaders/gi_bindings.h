// Descriptor bindings and push constants of ReSTIR GI and specular GI
// (docs/design.md §3 steps 7-8), shared by C++ and GLSL (host_device.h rules).
// Numbers 70-79 are reserved here; the G-buffer keeps its number from bindings.h.
#ifndef GI_GPU_SHADERS_GI_BINDINGS_H
#define GI_GPU_SHADERS_GI_BINDINGS_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

GI_CONST uint BINDING_GI_RESERVOIRS_STORED = 70u;  // GiReservoir[chains · pixels]: final, kept for next frame
GI_CONST uint BINDING_GI_RESERVOIRS_MID = 71u;     // GiReservoir[chains · pixels]: initial + temporal
GI_CONST uint BINDING_GI_SURFACES = 72u;           // GiSurface[pixels]: last frame's surfaces
GI_CONST uint BINDING_GI_OUTPUT = 73u;             // vec4[chains · pixels]: this frame's diffuse GI
GI_CONST uint BINDING_GI_ACCUMULATION = 74u;       // vec4[chains · pixels]: rgb sum over the window, w frames
GI_CONST uint BINDING_GI_STATS = 75u;              // GiStats: this frame's statistics (zeroed by the host)
GI_CONST uint BINDING_SPECULAR_OUTPUT = 76u;       // vec4[chains · pixels]: this frame's specular GI
GI_CONST uint BINDING_SPECULAR_ACCUMULATION = 77u; // vec4[chains · pixels]: rgb sum, w frames
GI_CONST uint BINDING_GI_COUNTERS = 79u;          // GiCounters (GI_PATH_COUNTERS; zeroed by the host)
GI_CONST uint BINDING_GI_RESERVOIRS_HISTORY = 78u; // GiReservoir[chains · pixels]: this frame's temporal merge,
                                                   // next frame's history (GI_TEMPORAL_HISTORY 1; else one slot)

struct GiPushConstants {
  uint chain_count;
  uint history_valid;  // 0 on the first frame: no temporal reuse
  uint accumulate;     // 1: add this frame to the accumulation
  uint permutation;    // this frame's permutation-sampling random (restir_gi.h gi_permute_pixel)
};

// Last frame's surface of a pixel, for temporal reuse.
struct GiSurface {
  vec4 position_view_z;  // xyz world position, w view depth (0: no surface)
  vec4 normal;           // xyz shading normal facing the camera
  vec4 base_color;       // rgb base colour, a metallic (the temporal target's base/π)
};

GI_SHADER_END

#endif
