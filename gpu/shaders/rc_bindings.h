// Bindings and push constants of the radiance-cascades passes
// (gpu/rc/, gpu/shaders/rc_*.comp, jfa_*.comp). Every "texture" is a storage
// buffer of canvas width × height texels, row-major (the cascades are at the
// canvas's resolution: the lesson's gi_scale is 1).
#ifndef GI_GPU_SHADERS_RC_BINDINGS_H
#define GI_GPU_SHADERS_RC_BINDINGS_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

GI_CONST uint BINDING_RC_SHAPES = 0u;          // RcShape[] (core/shared/rc/shapes.h)
GI_CONST uint BINDING_RC_SCENE = 1u;           // vec4[]: the lesson's tex_main, rgb radiance, a = 1 inside a shape
GI_CONST uint BINDING_RC_DISTANCE = 2u;        // float[]: unsigned distance to the nearest shape, pixels
GI_CONST uint BINDING_RC_SEEDS_IN = 3u;        // uint[]: JFA's nearest seed, x | y << 16 (RC_NO_SEED: none)
GI_CONST uint BINDING_RC_SEEDS_OUT = 4u;
GI_CONST uint BINDING_RC_CASCADE_SOURCE = 5u;  // vec4[]: the coarser cascade, merged (ping)
GI_CONST uint BINDING_RC_CASCADE_DEST = 6u;    // vec4[]: this cascade (pong)
GI_CONST uint BINDING_RC_MIPMAP = 7u;          // vec4[]: one texel per cascade-0 probe
GI_CONST uint BINDING_RC_OUTPUT = 8u;          // vec4[]: scene + radiance

GI_CONST uint RC_NO_SEED = 0xffffffffu;

// One push-constant block for every RC pass (each reads what it needs).
struct RcPush {
  uint width, height;    // the canvas
  uint shape_count;
  uint merge;            // rc_cascade: 1 to merge the coarser cascade into rays that miss
  uint probe_width;      // rc_cascade: this cascade's; rc_mipmap, rc_apply: cascade 0's
  float probe_start;
  float probe_range;
  uint max_steps;        // rc_cascade: the march's step limit
  float hit_epsilon;     // rc_cascade: a march hits below this distance
  uint jfa_step;         // jfa_step: the jump, pixels
  uint jfa_last;         // jfa_step: 1 on the last round, which writes the distance field
  uint mipmap_mode;      // rc_mipmap: RC_MIPMAP_* (core/shared/rc/cascades.h)
  uint mip_width, mip_height;
  uint merge_fix;        // rc_cascade: RC_MERGE_* (core/shared/rc/cascades.h)
  uint pad1;
};

GI_SHADER_END

#endif
