// ReSTIR GI and specular GI compile-time settings (from the profile, DESIGN §3
// steps 7-8) and the buffers their passes share. Each setting becomes a
// #define, so a scenario compiles only the variant it uses.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "gpu/shader_compiler.h"

namespace gi::gpu {

class Buffer;

struct GiSettings {
  float confidence_cap = 8.0f;
  float spatial_radius = 30.0f;
  std::uint32_t spatial_tries = 5;
  float plane_tolerance = 0.003f;
  float normal_min_dot = 0.906f;
  float jacobian_reject = 1.2f;
  bool jacobian_rejection = true;       // false: merge whatever J is (shows the jacobian check fires)
  bool temporal_permutation = true;
  // restir_gi.mis_weights "consistent": the canonical sample's MIS weight at
  // the other pixel includes its visibility from there (spatial: one more
  // ray) and is zero where the jacobian rejection would refuse that shift.
  // false ("solari"): Solari's weights, which darken GI.
  bool consistent_mis = false;
  // world_cache: Solari's query at the hit (pixel-rooted, insertions committed
  // by the cache after the GI passes); needs the world cache (Renderer).
  enum class HitRadiance { nee = 0, path = 1, world_cache = 2 } hit_radiance = HitRadiance::path;
  // brdf.secondary_hits "full": a GI sample's hit on a glossy surface is
  // followed along its BRDF, a rough hit adds its specular albedo; false:
  // Solari's diffuse-only secondary hits (hit_radiance.glsl).
  bool secondary_hits_full = false;
  float ray_tmax = 50.0f;               // the initial GI ray (world_cache.gi_ray_tmax)
  bool specular = true;                 // specular.enabled
  float specular_reuse_roughness = 0.4f;
  std::uint32_t specular_max_bounces = 3;
  float min_perceptual_roughness = 0.0316f;  // brdf.min_perceptual_roughness (0: no clamp)
  std::uint32_t chains = 1;             // independent chains, as DiSettings::chains

  // The world cache's defines (WorldCache::shader_defines), set by the
  // Renderer when hit_radiance is world_cache; added to defines().
  std::vector<ShaderDefine> world_cache_defines;

  bool queries_world_cache() const { return hit_radiance == HitRadiance::world_cache; }
  std::vector<ShaderDefine> defines() const;
};

struct GiBuffers {
  const Buffer* gbuffer = nullptr;
  const Buffer* stored = nullptr;
  const Buffer* mid = nullptr;
  const Buffer* surfaces = nullptr;
  const Buffer* output = nullptr;
  const Buffer* accumulation = nullptr;
  const Buffer* stats = nullptr;
  const Buffer* specular_output = nullptr;
  const Buffer* specular_accumulation = nullptr;
  // The world cache's buffers by binding number (WorldCache::buffer_table),
  // when the passes query it.
  std::vector<std::pair<std::uint32_t, const Buffer*>> world_cache;
};

}  // namespace gi::gpu
