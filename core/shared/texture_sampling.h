// Material textures as both renderers read them (glTF 2.0 metallic-roughness
// textures, KHR_texture_transform, the samplers' wrap modes). One lookup rule,
// shared by the shaders and the Embree reference, so the two agree by
// construction: mip level 0 with bilinear filtering (no ray differentials in
// either renderer, so no mip selection both could compute exactly). Colour
// textures (base colour, emissive) are sRGB and decoded per texel before
// filtering, as a GPU's sRGB formats do; the others are linear.
//
// Texels are RGBA8 packed in one uint (R in the low byte), every image of a
// scene in one array; GpuTextureImage says where each starts.
#ifndef GI_SHARED_TEXTURE_SAMPLING_H
#define GI_SHARED_TEXTURE_SAMPLING_H
#include "host_device.h"

GI_SHADER_BEGIN

GI_CONST uint TEXTURE_NONE = 0xFFFFFFFFu;

// glTF sampler wrap modes (core/gltf_import.cpp maps 10497, 33071, 33648).
GI_CONST uint TEXTURE_WRAP_REPEAT = 0u;
GI_CONST uint TEXTURE_WRAP_CLAMP_TO_EDGE = 1u;
GI_CONST uint TEXTURE_WRAP_MIRRORED_REPEAT = 2u;

// A material's texture slots, in glTF's order of importance.
GI_CONST uint TEXTURE_SLOT_BASE_COLOR = 0u;
GI_CONST uint TEXTURE_SLOT_METALLIC_ROUGHNESS = 1u;  // G roughness, B metallic
GI_CONST uint TEXTURE_SLOT_NORMAL = 2u;              // tangent space, +Y green
GI_CONST uint TEXTURE_SLOT_EMISSIVE = 3u;
GI_CONST uint TEXTURE_SLOT_COUNT = 4u;

// How the realtime pipeline reads a normal map (profile textures.normal_map_decode):
// SIGNED is glTF's texel · 2 − 1 (Bevy #24880, after v0.19.0); RAW the texel
// itself as the tangent-space normal at ray hits, as every release shipped it
// (v0.19.0:scene/raytracing_scene_bindings.wgsl:218), while the G-buffer
// (rasterised by bevy_pbr in Bevy) stays SIGNED (gbuffer_resolve.comp); NONE
// drops normal maps everywhere (what a renderer that ignores them draws).
// References always decode SIGNED: C++ never defines it,
// reference_path_trace.comp resets it.
GI_CONST uint NORMAL_MAP_DECODE_NONE = 0u;
GI_CONST uint NORMAL_MAP_DECODE_RAW = 1u;
GI_CONST uint NORMAL_MAP_DECODE_SIGNED = 2u;
#ifndef NORMAL_MAP_DECODE
#define NORMAL_MAP_DECODE 2
#endif

struct GpuTextureImage {
  uvec4 first_width_height;  // x first texel, y width, z height, w unused
};

// One texture reference of a material: the image, its sampler's wrap modes and
// the KHR_texture_transform as a 2×3 matrix on (u, v, 1).
struct GpuTextureSlot {
  vec4 transform_u;  // xyz: u' = dot(xyz, (u, v, 1)); w the normal map's scale
  vec4 transform_v;  // xyz: v' = dot(xyz, (u, v, 1)); w unused
  uvec4 image_wrap;  // x image (TEXTURE_NONE: no texture), y wrap S, z wrap T, w unused
};

// Parallel to the materials; read only for a material whose reflectance.z
// says it has textures, so untextured scenes never touch it.
struct GpuMaterialTextures {
  GpuTextureSlot slots[4];  // TEXTURE_SLOT_COUNT
};

// Parallel to the vertices; read only for textured materials.
struct GpuVertexAttributes {
  vec4 uv;       // xy TEXCOORD_0, zw unused
  vec4 tangent;  // xyz object-space tangent, w the bitangent sign (0: no tangent)
};

GI_FN vec2 texture_transform(GpuTextureSlot slot, vec2 uv) {
  vec3 h = vec3(uv.x, uv.y, 1.0f);
  return vec2(dot(vec3(slot.transform_u), h), dot(vec3(slot.transform_v), h));
}

// A texel coordinate folded into [0, size) by the wrap mode. Only non-negative
// operands reach `%` (GLSL leaves a negative one undefined).
GI_FN int wrap_texel(int i, int size, uint mode) {
  if (mode == TEXTURE_WRAP_CLAMP_TO_EDGE) return clamp(i, 0, size - 1);
  if (mode == TEXTURE_WRAP_MIRRORED_REPEAT) {
    int period = 2 * size;
    int m = i >= 0 ? i % period : period - 1 - ((-i - 1) % period);
    return m < size ? m : period - 1 - m;
  }
  return i >= 0 ? i % size : size - 1 - ((-i - 1) % size);
}

// The texture coordinate brought near [0, 1] before it is scaled to texels, so
// a large uv cannot overflow the integer conversion. Each mode's period keeps
// the lookup unchanged: 1 for repeat, 2 for mirrored repeat.
GI_FN float reduce_texture_coordinate(float u, uint mode) {
  if (mode == TEXTURE_WRAP_CLAMP_TO_EDGE) return clamp(u, -1.0f, 2.0f);
  if (mode == TEXTURE_WRAP_MIRRORED_REPEAT) return u - 2.0f * floor(0.5f * u);
  return u - floor(u);
}

GI_FN vec4 unpack_texel(uint t) {
  return vec4(float(t & 255u), float((t >> 8u) & 255u), float((t >> 16u) & 255u), float(t >> 24u)) *
         (1.0f / 255.0f);
}

GI_FN float srgb_to_linear(float c) {
  return c <= 0.04045f ? c * (1.0f / 12.92f) : pow((c + 0.055f) * (1.0f / 1.055f), 2.4f);
}

GI_FN vec4 decode_texel(uint t, bool srgb) {
  vec4 c = unpack_texel(t);
  if (srgb) c = vec4(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z), c.w);
  return c;
}

// The four texels a bilinear lookup at `uv` reads (pixel centres at half
// integers, as Vulkan's), wrapped, and the weight of the second column and
// row. Index k: x0y0, x1y0, x0y1, x1y1.
struct BilinearFootprint {
  uvec4 texel;  // indices into the scene's texel array
  vec2 weight;
};

GI_FN BilinearFootprint bilinear_footprint(GpuTextureImage image, GpuTextureSlot slot, vec2 uv) {
  int w = int(image.first_width_height.y), h = int(image.first_width_height.z);
  float x = reduce_texture_coordinate(uv.x, slot.image_wrap.y) * float(w) - 0.5f;
  float y = reduce_texture_coordinate(uv.y, slot.image_wrap.z) * float(h) - 0.5f;
  float fx = floor(x), fy = floor(y);
  int x0 = int(fx), y0 = int(fy);
  int xa = wrap_texel(x0, w, slot.image_wrap.y), xb = wrap_texel(x0 + 1, w, slot.image_wrap.y);
  int ya = wrap_texel(y0, h, slot.image_wrap.z), yb = wrap_texel(y0 + 1, h, slot.image_wrap.z);
  uint first = image.first_width_height.x;
  BilinearFootprint f;
  f.texel = uvec4(first + uint(ya * w + xa), first + uint(ya * w + xb), first + uint(yb * w + xa),
                  first + uint(yb * w + xb));
  f.weight = vec2(x - fx, y - fy);
  return f;
}

GI_FN vec4 bilinear_blend(vec4 c00, vec4 c10, vec4 c01, vec4 c11, vec2 weight) {
  vec4 top = c00 + (c10 - c00) * weight.x;
  vec4 bottom = c01 + (c11 - c01) * weight.x;
  return top + (bottom - top) * weight.y;
}

// A tangent-space normal `m` (a decoded normal-map texel) turned into a
// shading normal: glTF's tangent frame (bitangent = cross(n, t) · sign), m's xy
// scaled by normalTexture.scale. The tangent is made orthogonal to n first, as
// MikkTSpace's consumers do.
GI_FN vec3 perturb_normal(vec3 n, vec3 tangent, float bitangent_sign, vec3 m, float scale) {
  vec3 t = tangent - n * dot(n, tangent);
  float tl = length(t);
  if (!(tl > 0.0f)) return n;
  t = t / tl;
  vec3 b = cross(n, t) * bitangent_sign;
  vec3 p = t * (m.x * scale) + b * (m.y * scale) + n * m.z;
  float pl = length(p);
  return pl > 0.0f ? p / pl : n;
}

GI_SHADER_END

#endif
