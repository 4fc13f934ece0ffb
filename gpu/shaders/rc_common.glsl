// What every radiance-cascades pass declares: its push constants and a
// one-texel-per-invocation 8×8 layout over a width × height grid.
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/rc_bindings.h"
#include "core/shared/rc/cascades.h"

layout(push_constant) uniform Push { RcPush pc; };
layout(local_size_x = RC_GROUP, local_size_y = RC_GROUP) in;

uint rc_texel(uvec2 p) { return p.y * pc.width + p.x; }
