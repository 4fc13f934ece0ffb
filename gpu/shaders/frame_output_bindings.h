// Bindings and result layouts of the observation passes (frame_output.comp,
// buffer_hash.comp): what the harness reduces on the GPU so that a frame's
// record reads back a few bytes instead of its images (host_device.h rules).
#ifndef GI_GPU_SHADERS_FRAME_OUTPUT_BINDINGS_H
#define GI_GPU_SHADERS_FRAME_OUTPUT_BINDINGS_H
#include "core/shared/host_device.h"

GI_SHADER_BEGIN

GI_CONST uint BINDING_HASH_SUMS = 90u;            // uvec2[] per slot: the lane sums (word_hash.h)
GI_CONST uint BINDING_FRAME_SIGNAL_0 = 91u;       // vec4[]: realtime DI (chain A first) | reference half A
GI_CONST uint BINDING_FRAME_SIGNAL_1 = 92u;       // vec4[]: realtime GI | reference half B
GI_CONST uint BINDING_FRAME_SIGNAL_2 = 93u;       // vec4[]: realtime specular GI
GI_CONST uint BINDING_FRAME_IMAGE = 94u;          // float[3 * pixels]: the output, rgb, tightly packed
GI_CONST uint BINDING_FRAME_PARTIALS = 95u;       // double[FRAME_SIGNALS] per workgroup
GI_CONST uint BINDING_FRAME_RESULTS = 96u;        // FrameOutputResults
GI_CONST uint BINDING_FRAME_NOISE_SUMS = 97u;     // double[6] per pixel and signal: rgb sum, rgb sum of squares

GI_CONST uint BUFFER_HASH_GROUP = 64u;
// A workgroup of FRAME_OUTPUT_GROUP invocations covers FRAME_OUTPUT_GROUP ·
// FRAME_OUTPUT_PIXELS_PER_INVOCATION consecutive pixels, invocation i the
// pixels i, i + GROUP, i + 2·GROUP, … (adjacent lanes read adjacent pixels),
// each adding its own in that order: fewer workgroups and barriers than a
// pixel per invocation (lavapipe runs a workgroup's barriers serially).
GI_CONST uint FRAME_OUTPUT_GROUP = 64u;
GI_CONST uint FRAME_OUTPUT_PIXELS_PER_INVOCATION = 8u;
GI_CONST uint FRAME_OUTPUT_GROUP_PIXELS = 512u;  // the product of the two

// The signals a frame's record measures, in this order.
GI_CONST uint FRAME_SIGNAL_OUTPUT = 0u;
GI_CONST uint FRAME_SIGNAL_DI = 1u;
GI_CONST uint FRAME_SIGNAL_GI = 2u;
GI_CONST uint FRAME_SIGNAL_SPECULAR = 3u;
GI_CONST uint FRAME_SIGNALS = 4u;

// What the output is made of.
GI_CONST uint FRAME_OUTPUT_DI = 0u;         // realtime without GI: DI
GI_CONST uint FRAME_OUTPUT_DI_GI = 1u;      // realtime with GI: (DI + GI) + specular
GI_CONST uint FRAME_OUTPUT_REFERENCE = 2u;  // reference: (A + B) / (nA + nB)

struct FrameOutputPush {
  uint pixels;
  uint mode;              // FRAME_OUTPUT_*
  uint accumulate_noise;  // 1: add the signals to the temporal-noise sums
  uint groups;            // workgroups of the first dispatch (the partials the reduction reads)
};

// A signal's luminance is summed (in double, in a fixed order) over its
// finite pixels only, as core/metrics.h mean_luminance does.
struct FrameOutputResults {
  double luminance_sum[4];        // per FRAME_SIGNAL_*
  uint finite_pixels[4];
  uint nonfinite_components;      // of the output: channels that are inf or NaN
  uint pad0, pad1, pad2;
};

GI_SHADER_END

#endif
