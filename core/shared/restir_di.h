// Pure helpers of ReSTIR DI (docs/design.md §3 step 6) shared by the GPU passes and the
// CPU tests (host_device.h rules). Scene-dependent parts live in
// light_sampling.h (bridge-included).
#ifndef GI_SHARED_RESTIR_DI_H
#define GI_SHARED_RESTIR_DI_H
#include "host_device.h"
#include "light_tiles.h"
#include "rng.h"

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
  vec4 diffuse;          // rgb the target's colour: base colour (restir_di.target base_over_pi)
                         // or base colour · (1 − metallic) (diffuse_brdf)
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

// The resampling target: luminance of the unshadowed contribution times
// colour/π. Solari passes the base colour (base_color / PI, metallic ignored,
// so metals are sampled too); the harness's old choice passed the diffuse
// colour base · (1 − metallic), which gives pure metals a zero target and so
// no DI (profile key restir_di.target).
GI_FN float di_target(LightContribution c, vec3 diffuse_color) {
  return luminance(c.received_radiance * diffuse_color * INV_PI);
}

// The light tile an 8×8 workgroup draws its initial candidates from when the
// tile is chosen per workgroup (restir_di.tile_choice = workgroup): one PCG
// step of a seed built from the workgroup id alone, so it stays the same
// every frame and in every run (Solari's generate_initial_reservoir; the
// tiles' contents change every frame).
GI_FN uint di_workgroup_tile(uvec2 workgroup, uint tile_count) {
  return pcg_hash(workgroup.x * 5782582u + workgroup.y) % tile_count;
}

// Solari 0.18's frame index as its push constants carry it: the frame count
// times 5782582 (wrapping). The temporal permutation takes its offsets from it.
GI_FN uint di_permutation_random(uint frame_index) { return frame_index * 5782582u; }

// Permutation sampling of the reprojected pixel (restir_di.temporal_permutation):
// offset o = (r & 3, (r >> 2) & 3), q = ((p + o) ^ 3) − o in unsigned
// arithmetic, then min(q, resolution − 1). As in Solari, a result below 0
// wraps and lands on the last row or column (pixel_dissimilar then usually
// rejects it and point reprojection is tried).
GI_FN uvec2 di_permute_pixel(uvec2 p, uint r, uvec2 resolution) {
  uvec2 offset = uvec2(r & 3u, (r >> 2u) & 3u);
  uvec2 q = ((p + offset) ^ uvec2(3u, 3u)) - offset;
  return min(q, resolution - uvec2(1u, 1u));
}

GI_SHADER_END

#endif
