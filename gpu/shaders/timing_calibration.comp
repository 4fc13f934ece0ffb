// A fixed amount of work whose time says how fast the device is right now
//: on lavapipe the "GPU" is this machine's CPU, shared with
// whatever else runs, so a pass's milliseconds mean little alone. Each frame
// dispatches this kernel last, timed on its own; the nightly compares pass
// times as multiples of it (reports/timing_verdict.h), so a baseline taken on
// a machine twice as fast, or under a concurrent build, still compares.
//
// The work mixes what the pipeline's passes do: dependent integer hashing
// (the RNG), float arithmetic (shading) and reads at hashed addresses of a
// table bigger than L1 (BVH and reservoir fetches). Its output is written so
// the compiler cannot drop the loop; nothing reads it.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/timing_calibration_bindings.h"

layout(std430, set = 0, binding = BINDING_CALIBRATION_TABLE) buffer Table { uint table[]; };

layout(push_constant) uniform Push {
  uint iterations;
} pc;

layout(local_size_x = CALIBRATION_GROUP) in;

void main() {
  const uint id = gl_GlobalInvocationID.x;
  uint h = id * 747796405u + 2891336453u;
  float f = float(id & 255u) * (1.0 / 256.0);
  uint acc = 0u;
  for (uint i = 0u; i < pc.iterations; ++i) {
    h = h * 747796405u + 2891336453u;  // PCG's LCG step
    const uint word = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    acc += table[(word >> 8u) & (CALIBRATION_TABLE_WORDS - 1u)];
    f = fma(f, 0.999, float(word & 1023u) * (1.0 / 1024.0));
  }
  // The table is zero and never written (acc stays 0, f stays below 1e30),
  // so this store never happens; the compiler cannot know that, so the loop
  // and its reads stay.
  if (acc != 0u || f > 1.0e30) table[id & (CALIBRATION_TABLE_WORDS - 1u)] = acc + uint(f);
}
