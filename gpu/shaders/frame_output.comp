// The frame's output made on the GPU, and what the frame record measures of
// it, reduced there: the output image (realtime: chain A's
// (DI + GI) + specular, in the order the CPU added them; reference: the two
// halves' mean), per signal the luminance summed over finite pixels in
// double and in a fixed tree order, the finite pixels and the output's
// non-finite channels counted with integer atomics, and, on the temporal
// noise window's frames, each pixel's running sums for signal_noise.h.
//
// Compiled twice: the per-pixel pass, and with FRAME_OUTPUT_REDUCE the
// one-workgroup pass that adds the workgroups' partial sums in a fixed order.
#version 460
#extension GL_GOOGLE_include_directive : require
#include "gpu/shaders/frame_output_bindings.h"

layout(std430, set = 0, binding = BINDING_FRAME_PARTIALS) buffer Partials { double partials[]; };
layout(std430, set = 0, binding = BINDING_FRAME_RESULTS) buffer Results { FrameOutputResults results; };
layout(push_constant) uniform Push { FrameOutputPush pc; };

layout(local_size_x = FRAME_OUTPUT_GROUP) in;

shared double group_sums[FRAME_SIGNALS][FRAME_OUTPUT_GROUP];

// Adds group_sums[s][*] into group_sums[s][0], always pairing the same slots.
void reduce_group_sums() {
  for (uint stride = FRAME_OUTPUT_GROUP / 2u; stride > 0u; stride /= 2u) {
    barrier();
    if (gl_LocalInvocationIndex < stride)
      for (uint s = 0u; s < FRAME_SIGNALS; ++s)
        group_sums[s][gl_LocalInvocationIndex] += group_sums[s][gl_LocalInvocationIndex + stride];
  }
  barrier();
}

#ifdef FRAME_OUTPUT_REDUCE

void main() {
  const uint t = gl_LocalInvocationIndex;
  for (uint s = 0u; s < FRAME_SIGNALS; ++s) {
    double sum = 0.0LF;
    for (uint g = t; g < pc.groups; g += FRAME_OUTPUT_GROUP) sum += partials[g * FRAME_SIGNALS + s];
    group_sums[s][t] = sum;
  }
  reduce_group_sums();
  if (t == 0u)
    for (uint s = 0u; s < FRAME_SIGNALS; ++s) results.luminance_sum[s] = group_sums[s][0];
}

#else

layout(std430, set = 0, binding = BINDING_FRAME_SIGNAL_0) readonly buffer Signal0 { vec4 signal0[]; };
layout(std430, set = 0, binding = BINDING_FRAME_SIGNAL_1) readonly buffer Signal1 { vec4 signal1[]; };
layout(std430, set = 0, binding = BINDING_FRAME_SIGNAL_2) readonly buffer Signal2 { vec4 signal2[]; };
layout(std430, set = 0, binding = BINDING_FRAME_IMAGE) writeonly buffer Image { float image[]; };
layout(std430, set = 0, binding = BINDING_FRAME_NOISE_SUMS) buffer NoiseSums { double noise_sums[]; };

shared uint group_finite[FRAME_SIGNALS];
shared uint group_nonfinite;

bool finite3(vec3 c) { return !any(isnan(c)) && !any(isinf(c)); }

// luminance() of host_device.h with the products and sums in the order the
// C++ build evaluates them (GLM's dot: (x + y) + z) and no fused multiply-add.
float luminance_exact(vec3 c) {
  precise float l = c.r * 0.2126f + c.g * 0.7152f;
  precise float sum = l + c.b * 0.0722f;
  return sum;
}

void accumulate_noise(uint signal, uint pixel, vec3 x) {
  const uint at = (signal * pc.pixels + pixel) * 6u;
  const dvec3 d = dvec3(x);
  for (uint c = 0u; c < 3u; ++c) {
    precise double sum = noise_sums[at + c] + d[c];
    precise double sq = d[c] * d[c];
    precise double sum_sq = noise_sums[at + 3u + c] + sq;
    noise_sums[at + c] = sum;
    noise_sums[at + 3u + c] = sum_sq;
  }
}

// One pixel: the output written, its signals' luminance added to `sums`
// when finite (counted in `finite`), the output's bad channels counted.
void shade_pixel(uint pixel, inout double sums[FRAME_SIGNALS], inout uint finite[FRAME_SIGNALS], inout uint bad) {
  vec3 signals[FRAME_SIGNALS];
  uint count = 1u;
  if (pc.mode == FRAME_OUTPUT_REFERENCE) {
    const vec4 a = signal0[pixel], b = signal1[pixel];
    precise float n = a.w + b.w;
    precise vec3 sum = a.rgb + b.rgb;
    signals[FRAME_SIGNAL_OUTPUT] = n > 0.0f ? sum / n : vec3(0.0f);
  } else {
    signals[FRAME_SIGNAL_DI] = signal0[pixel].rgb;
    count = 2u;
    precise vec3 out_rgb = signals[FRAME_SIGNAL_DI];
    if (pc.mode == FRAME_OUTPUT_DI_GI) {
      signals[FRAME_SIGNAL_GI] = signal1[pixel].rgb;
      signals[FRAME_SIGNAL_SPECULAR] = signal2[pixel].rgb;
      count = FRAME_SIGNALS;
      out_rgb = (out_rgb + signals[FRAME_SIGNAL_GI]) + signals[FRAME_SIGNAL_SPECULAR];
    }
    signals[FRAME_SIGNAL_OUTPUT] = out_rgb;
  }
  const vec3 o = signals[FRAME_SIGNAL_OUTPUT];
  image[3u * pixel] = o.r;
  image[3u * pixel + 1u] = o.g;
  image[3u * pixel + 2u] = o.b;
  bad += uint(isnan(o.r) || isinf(o.r)) + uint(isnan(o.g) || isinf(o.g)) + uint(isnan(o.b) || isinf(o.b));
  for (uint s = 0u; s < count; ++s) {
    if (finite3(signals[s])) {
      sums[s] += double(luminance_exact(signals[s]));
      ++finite[s];
    }
    if (pc.accumulate_noise != 0u) accumulate_noise(s, pixel, signals[s]);
  }
}

void main() {
  const uint t = gl_LocalInvocationIndex;
  if (t < FRAME_SIGNALS) group_finite[t] = 0u;
  if (t == 0u) group_nonfinite = 0u;
  barrier();

  double sums[FRAME_SIGNALS];
  uint finite[FRAME_SIGNALS];
  for (uint s = 0u; s < FRAME_SIGNALS; ++s) {
    sums[s] = 0.0LF;
    finite[s] = 0u;
  }
  uint bad = 0u;
  const uint first = gl_WorkGroupID.x * FRAME_OUTPUT_GROUP_PIXELS + t;
  for (uint k = 0u; k < FRAME_OUTPUT_PIXELS_PER_INVOCATION; ++k) {
    const uint pixel = first + k * FRAME_OUTPUT_GROUP;
    if (pixel < pc.pixels) shade_pixel(pixel, sums, finite, bad);
  }
  for (uint s = 0u; s < FRAME_SIGNALS; ++s) {
    group_sums[s][t] = sums[s];
    if (finite[s] > 0u) atomicAdd(group_finite[s], finite[s]);
  }
  if (bad > 0u) atomicAdd(group_nonfinite, bad);
  reduce_group_sums();
  if (t < FRAME_SIGNALS) {
    partials[gl_WorkGroupID.x * FRAME_SIGNALS + t] = group_sums[t][0];
    atomicAdd(results.finite_pixels[t], group_finite[t]);
  }
  if (t == 0u) atomicAdd(results.nonfinite_components, group_nonfinite);
}

#endif
