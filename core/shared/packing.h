// Bit packings shared by the GPU passes and the CPU (host_device.h rules):
// rgb9e5 (a shared 5-bit exponent, three 9-bit mantissas; the classic
// GL_EXT_texture_shared_exponent encoder, which Bevy's bevy_pbr::rgb9e5 also
// follows), its log2 variant that Solari 0.18 uses for light-tile radiance, and
// octahedral unit vectors in two 16-bit unorms.
#ifndef GI_SHARED_PACKING_H
#define GI_SHARED_PACKING_H
#include "host_device.h"

GI_SHADER_BEGIN

GI_CONST int RGB9E5_EXPONENT_BITS = 5;
GI_CONST int RGB9E5_MANTISSA_BITS = 9;
GI_CONST int RGB9E5_EXP_BIAS = 15;
GI_CONST int RGB9E5_MANTISSA_VALUES = 512;
// Largest encodable value: (511 / 512) · 2^16. Anything brighter is clipped,
// which is how plain rgb9e5 loses the energy of very bright lights.
GI_CONST float RGB9E5_MAX = 65408.0f;

GI_FN int floor_log2_bits(float x) {
  return int((floatBitsToUint(x) & 0x7F800000u) >> 23u) - 127;
}

// Round to nearest; negative and NaN channels become 0, large ones clip to RGB9E5_MAX.
GI_FN uint vec3_to_rgb9e5(vec3 rgb_in) {
  vec3 rgb = clamp(rgb_in, vec3(0.0f), vec3(RGB9E5_MAX));
  // clamp keeps a NaN in GLSL on some drivers: force it to 0.
  if (!(rgb.x >= 0.0f)) rgb.x = 0.0f;
  if (!(rgb.y >= 0.0f)) rgb.y = 0.0f;
  if (!(rgb.z >= 0.0f)) rgb.z = 0.0f;
  float maxrgb = max(rgb.x, max(rgb.y, rgb.z));
  int exp_shared = max(-RGB9E5_EXP_BIAS - 1, floor_log2_bits(maxrgb)) + 1 + RGB9E5_EXP_BIAS;
  float denom = exp2(float(exp_shared - RGB9E5_EXP_BIAS - RGB9E5_MANTISSA_BITS));
  int maxm = int(floor(maxrgb / denom + 0.5f));
  if (maxm == RGB9E5_MANTISSA_VALUES) {
    denom *= 2.0f;
    exp_shared += 1;
  }
  uint r = uint(floor(rgb.x / denom + 0.5f));
  uint g = uint(floor(rgb.y / denom + 0.5f));
  uint b = uint(floor(rgb.z / denom + 0.5f));
  return (uint(exp_shared) << 27u) | (b << 18u) | (g << 9u) | r;
}

GI_FN vec3 rgb9e5_to_vec3(uint v) {
  int exponent = int(v >> 27u) - RGB9E5_EXP_BIAS - RGB9E5_MANTISSA_BITS;
  float scale = exp2(float(exponent));
  return vec3(float(v & 511u), float((v >> 9u) & 511u), float((v >> 18u) & 511u)) * scale;
}

// Solari 0.18's light-tile radiance: rgb9e5(log2(L·exposure + 1)), decoded
// (exp2(x) − 1)/exposure. The range grows to ~2^65408; the price is a relative
// error of up to ln 2 · (step/2) in log space per channel.
GI_FN uint pack_radiance_log2(vec3 radiance, float exposure) {
  return vec3_to_rgb9e5(log2(radiance * exposure + vec3(1.0f)));
}
GI_FN vec3 unpack_radiance_log2(uint packed, float exposure) {
  return (exp2(rgb9e5_to_vec3(packed)) - vec3(1.0f)) / exposure;
}
// Solari 0.17: plain rgb9e5(L·exposure).
GI_FN uint pack_radiance_plain(vec3 radiance, float exposure) { return vec3_to_rgb9e5(radiance * exposure); }
GI_FN vec3 unpack_radiance_plain(uint packed, float exposure) { return rgb9e5_to_vec3(packed) / exposure; }

GI_FN uint pack_radiance(vec3 radiance, float exposure, bool log2_encoding) {
  return log2_encoding ? pack_radiance_log2(radiance, exposure) : pack_radiance_plain(radiance, exposure);
}
GI_FN vec3 unpack_radiance(uint packed, float exposure, bool log2_encoding) {
  return log2_encoding ? unpack_radiance_log2(packed, exposure) : unpack_radiance_plain(packed, exposure);
}

// Octahedral map of a unit vector to [0, 1]² (Cigolle et al., JCGT 2014).
GI_FN vec2 octahedral_encode(vec3 n) {
  vec3 v = n / (abs(n.x) + abs(n.y) + abs(n.z));
  vec2 e = vec2(v.x, v.y);
  if (v.z < 0.0f) {
    vec2 s = vec2(e.x >= 0.0f ? 1.0f : -1.0f, e.y >= 0.0f ? 1.0f : -1.0f);
    e = (vec2(1.0f) - abs(vec2(e.y, e.x))) * s;
  }
  return e * 0.5f + vec2(0.5f);
}

GI_FN vec3 octahedral_decode(vec2 uv) {
  vec2 f = uv * 2.0f - vec2(1.0f);
  vec3 n = vec3(f.x, f.y, 1.0f - abs(f.x) - abs(f.y));
  float t = saturate(-n.z);
  n.x += n.x >= 0.0f ? -t : t;
  n.y += n.y >= 0.0f ? -t : t;
  return normalize(n);
}

GI_FN uint pack_unit_vector(vec3 n) { return packUnorm2x16(octahedral_encode(n)); }
GI_FN vec3 unpack_unit_vector(uint p) { return octahedral_decode(unpackUnorm2x16(p)); }

GI_SHADER_END

#endif
