// Pure helpers of ReSTIR DI (DESIGN §3 step 6) shared by the GPU passes and the
// CPU tests (host_device.h rules). Scene-dependent parts live in
// light_sampling.h (bridge-included).
#ifndef GI_SHARED_RESTIR_DI_H
#define GI_SHARED_RESTIR_DI_H
#include "host_device.h"
#include "light_tiles.h"

GI_SHADER_BEGIN

// Random streams of the realtime DI passes, one per independent chain
// (DiChains): added to the chain index.
GI_CONST uint RNG_DOMAIN_LIGHT_TILES = 0x27D4EB2Fu;
GI_CONST uint RNG_DOMAIN_DI_INITIAL = 0x165667B1u;
GI_CONST uint RNG_DOMAIN_DI_SPATIAL = 0xD3A2646Cu;
GI_CONST uint LIGHT_ID_GONE = 0xFFFFFFFFu;

// What pass 2 leaves for next frame's temporal reuse of a pixel: its surface.
struct DiSurface {
  vec4 position_view_z;  // xyz world position, w view depth (0: no surface)
  vec4 normal;           // xyz shading normal facing the camera
  vec4 diffuse;          // rgb diffuse colour (base colour · (1 − metallic))
};

// Solari's pixel_dissimilar (NVIDIA, "Fast Denoising with Self-Stabilizing
// Recurrent Blurs", GTC 2020, p. 45): reject reuse across pixels whose
// surfaces differ — tangent-plane distance over view depth above
// `plane_tolerance` (0.003), or normals further apart than acos(`normal_min_dot`)
// (0.906 ≈ 25°).
GI_FN bool pixel_dissimilar(float view_z, vec3 position, vec3 other_position, vec3 normal, vec3 other_normal,
                            float plane_tolerance, float normal_min_dot) {
  float tangent_plane_distance = abs(dot(normal, other_position - position));
  return tangent_plane_distance / max(view_z, 1e-20f) > plane_tolerance || dot(normal, other_normal) < normal_min_dot;
}

// The resampling target: luminance of the unshadowed contribution times the
// diffuse BRDF (Solari's choice for DI, DESIGN §3 step 6).
GI_FN float di_target(LightContribution c, vec3 diffuse_color) {
  return luminance(c.received_radiance * diffuse_color * INV_PI);
}

GI_SHADER_END

#endif
