// ReSTIR GI and specular GI compile-time settings (from the profile, docs/design.md §3
// steps 7-8) and the buffers their passes share. Each setting becomes a
// #define, so a scenario compiles only the variant it uses.
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "gpu/shader_compiler.h"

namespace gi::gpu {

class Buffer;

// Filled by the profile table (gpu/profile_keys.cpp): a profile-filled field
// has no value of its own here (value-initialised; every value is the
// profile's). The run's own fields (the instrumentation flags, chains,
// specular_handover_alpha, world_cache_defines) keep theirs.
struct GiSettings {
  float confidence_cap{};
  // restir_gi.initial_samples: rays resampled into the initial reservoir
  // (Solari: 1; more is a harness knob).
  std::uint32_t initial_samples{};
  float spatial_radius{};
  std::uint32_t spatial_tries{};
  float plane_tolerance{};
  float normal_min_dot{};
  float jacobian_reject{};
  bool jacobian_rejection{};       // false: merge whatever J is (shows the jacobian check fires)
  // restir_gi.jacobian_rejection_directions "both" (Solari 0.19): also reject
  // when the canonical sample's jacobian towards the other pixel exceeds the
  // threshold; "one" (0.17, 0.18): the other sample's only.
  bool jacobian_both{};
  bool temporal_permutation{};
  // restir_gi.temporal_reuse false (harness-only, for the speed-against-error GI noise
  // breakdown): no temporal reuse at all; true is every release's.
  bool temporal_reuse{};
  // Instrumentation, compiled in only for a check that reads it
  // (temporal_acceptance): chain A's temporal reuse at edge pixels, counted
  // into GiStats.temporal_edge_pixels / temporal_edge_reused.
  bool temporal_edge_stats = false;
  // Instrumentation likewise (ray_budget, spatial_acceptance): the glossy
  // paths' closest-hit rays and the spatial search's outcome, chain A, into
  // GiCounters (a buffer that exists only then).
  bool path_counters = false;
  bool spatial_radius_halving{};  // restir_di.spatial_search (DiSettings::spatial_radius_halving)
  bool spatial_disk_clamped{};    // restir_di.spatial_disk (DiSettings::spatial_disk_clamped)
  // What temporal reuse does when the permuted pixel is unusable
  // (restir_gi.temporal_fallback): none (one try), point (Solari 0.18: the
  // unpermuted reprojection when the permuted surface differs or its
  // reservoir has no radiance), retry (Solari 0.17: up to 4 permutations).
  enum class TemporalFallback { none = 0, point = 1, retry = 2 } temporal_fallback{};
  // restir_gi.temporal_history "temporal": next frame's temporal reuse reads
  // this frame's temporal merge (before spatial reuse) from its own buffer;
  // false ("spatial", Solari: v0.18.0 realtime/restir_gi.wgsl:74,159): it
  // reads the stored spatial merge, so a neighbour's sample re-enters
  // history with the confidence of both pixels.
  bool temporal_history_pre_spatial{};
  // restir_gi.target "base_over_pi": the resampling target includes the
  // shading point's base colour / π, as Solari's; false: luminance(L)·cos.
  bool target_brdf{};
  // restir_gi.empty_samples "no_confidence": a miss or an emissive hit gives
  // a reservoir of confidence 0 (Solari); false: it counts as M = 1.
  bool empty_no_confidence{};
  // restir_gi.emissive_hit_test: which hits count as emitters (the GI sample
  // is then empty): "front_any_channel" (harness), "all_channels" (Solari
  // 0.17/0.18: all(emissive != 0), either face), "any_channel" (0.19).
  enum class EmissiveTest { front_any_channel = 0, all_channels = 1, any_channel = 2 } emissive_test =
      EmissiveTest::all_channels;
  // restir_gi.visibility "final": merges ignore visibility, the stored
  // reservoir is the merge, the final sample's ray only scales this frame's
  // shading (Solari 0.18); false: the spatial neighbour is tested before the
  // merge and the result stored (Solari 0.17).
  bool visibility_final{};
  // restir_gi.visibility "final_stored" (Bevy f94997ca37 #21649 to 37023731b9^
  // #21919): the final ray zeroes the stored reservoir's radiance, so next
  // frame reuses an occluded sample as dark, and this frame's shading takes
  // no visibility at all.
  bool visibility_final_stored{};
  // restir_gi.shading_cosine "twice" (Bevy bf728759f0 #22468 to 11b81eb1d7^
  // #23968, unreleased): the merged sample's radiance carries cos(θ) and the
  // diffuse BRDF it is shaded with carries it again.
  bool cosine_twice{};
  // restir_gi.diffuse_shading "diffuse": GI shaded with base·(1 − metallic)/π
  // (Solari 0.18); false: base/π whatever the metallic (Solari 0.17).
  bool shading_diffuse{};
  // restir_gi.smooth_metals "skip" (Solari 0.19): no ReSTIR GI at a pixel
  // with metallic > 0.9999 and alpha ≤ specular.reuse_gi_roughness, whose
  // light specular GI carries alone; its reservoirs stay empty, so neither
  // it nor its neighbours reuse a sample there, and it makes no cache query.
  // false ("run", 0.17 and 0.18): GI runs everywhere.
  bool skip_smooth_metals{};
  // restir_di.offscreen_reprojection "own_pixel" (0.19): GI's temporal reuse
  // of a pixel off screen last frame starts from the pixel itself; "none":
  // no history (DiSettings::offscreen_own_pixel, the same key).
  bool offscreen_own_pixel{};
  // restir_gi.mis_weights "consistent": the canonical sample's MIS weight at
  // the other pixel includes its visibility from there (spatial: one more
  // ray) and is zero where the jacobian rejection would refuse that shift.
  // false ("solari"): Solari's weights, which darken GI.
  bool consistent_mis{};
  // world_cache: Solari's query at the hit (pixel-rooted, insertions committed
  // by the cache after the GI passes); needs the world cache (Renderer).
  enum class HitRadiance { nee = 0, path = 1, world_cache = 2 } hit_radiance{};
  // brdf.secondary_hits "full": a GI sample's hit on a glossy surface is
  // followed along its BRDF, a rough hit adds its specular albedo; false:
  // Solari's diffuse-only secondary hits (hit_radiance.glsl).
  bool secondary_hits_full{};
  // brdf.secondary_albedo "base_color": a secondary hit reflects its full base
  // colour diffusely (Solari, metals included); false: base·(1 − metallic).
  bool secondary_albedo_base{};
  // world_cache.hit_normal "vertex" (Solari): a GI sample's or glossy path's
  // hit queries the cache with its interpolated vertex normal, unflipped (a
  // back face keys its front's cell); false: the face normal facing the ray.
  bool hit_cache_normal_vertex{};
  // restir_gi.sample_normal "shading" (Solari): a GI sample keeps its hit's
  // shading normal, unflipped, for the reuse jacobian (a back-face sample's
  // jacobian is 0); false: the face normal facing the pixel that found it.
  bool sample_normal_shading{};
  float ray_tmax{};                // the initial GI ray (restir_gi.ray_tmax)
  bool specular{};                 // specular.enabled
  float specular_reuse_roughness{};
  bool specular_power_mis{};       // specular.mis "power" (Solari 0.18); false: balance
  // specular.path_end "path_spread": a glossy path ends in the cache when its
  // footprint outgrows the cell (Solari 0.18, hit_radiance.glsl
  // GlossyPathEnd); false ("roughness"): at the first hit rougher than
  // specular_reuse_roughness.
  bool specular_path_spread{};
  // specular.path_end "long_ray_rough_path" (Solari 0.19): the third vertex,
  // or a ray longer than √3 cells once the path's summed alpha exceeds
  // specular.reuse_gi_roughness (secondary_hit.h, GlossyPathEnd).
  bool specular_path_long_ray{};
  // specular.path_end "cache_every_vertex" (Bevy main between #21355 and
  // #21907, never released): the cache's light added at every vertex of a
  // glossy path that goes on along the GGX lobe, no emission, no NEE
  // (specular_gi.comp, trace_glossy_path_cache_every_vertex).
  bool specular_cache_every_vertex{};
  // specular.russian_roulette (Solari 0.19): after each glossy bounce.
  bool specular_russian_roulette{};
  // specular.vndf_mirror_alpha: sampling returns the exact reflection at or
  // below this alpha (0.001; 0.01 re-creates the state #22240 fixed).
  float specular_vndf_mirror_alpha{};
  // specular.mis_light_pdf "area": the glossy path's MIS weighs the light's
  // area-measure pdf against the bounce's solid-angle one (every release;
  // #24671 put both in solid angle, "solid_angle").
  bool specular_mis_light_pdf_area{};
  // specular.perfect_mirror "alpha_and_metallic" (0.18, 0.19): a glossy
  // path's vertex skips NEE only at alpha <= 0.001 and metallic > 0.9999;
  // "alpha": at any metallic.
  bool specular_perfect_mirror_metal{};
  // specular.directional_lights "nee_only" (0.18, 0.19): a directional
  // light's NEE sample at weight 1, an escaped bounce adds nothing; "mis":
  // NEE weighed against the bounce, which adds the sun when it escapes.
  bool specular_sun_nee_only{};
  // specular.mirror_throughput "full_brdf" (0.19, realtime specular GI
  // only): at a glossy path's vertex of alpha <= 0.001 the exact reflection,
  // weighted by the whole BRDF·cos with no pdf (a smooth dielectric adds its
  // diffuse lobe), NEE there at weight 1; false ("sampled"): the sampled
  // lobe mixture's f·cos/pdf.
  bool specular_mirror_throughput_brdf{};
  // brdf.mirror "exact" (0.19, #22468): a mirror's sampled reflection weighs
  // the Fresnel term alone; "clamped_ggx" (0.18) the alpha-0.001 GGX lobe
  // over its pdf.
  bool specular_mirror_exact{};
  // brdf.sampling_frame "mikktspace" (0.18): a glossy path's bounce at a hit
  // with a mesh tangent samples in the skewed mesh frame (#23948 fixed it).
  bool specular_mesh_tangent_frame{};
  // specular.di_handover_alpha: at a primary alpha ≤ this the glossy path
  // counts its first hit's emission (weight 1: DI left the lobe to it).
  // Negative: never (DI owns the first hit everywhere).
  float specular_handover_alpha = -1.0f;
  std::uint32_t specular_max_bounces{};
  float min_perceptual_roughness{};  // brdf.min_perceptual_roughness (0: no clamp)
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
  const Buffer* history = nullptr;
  const Buffer* counters = nullptr;  // GiSettings::path_counters
  // The world cache's buffers by binding number (WorldCache::buffer_table),
  // when the passes query it.
  std::vector<std::pair<std::uint32_t, const Buffer*>> world_cache;
};

}  // namespace gi::gpu
