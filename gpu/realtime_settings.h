// What a Solari profile decides (docs/design.md §3): every key of
// scenarios/profiles/solari-*.json resolved once per run into one object,
// through the profile table (gpu/profile_keys.cpp, the only place a key is
// named). replay/run_setup.h builds it and hands its parts to the renderer
// and the checks.
#pragma once
#include <cstdint>
#include <string>

#include "core/profile.h"
#include "core/scene.h"
#include "core/scene_flatten.h"
#include "gpu/passes/gbuffer_resolve.h"
#include "gpu/passes/restir_di_settings.h"
#include "gpu/passes/restir_gi_settings.h"
#include "gpu/passes/world_cache.h"

namespace gi {

struct RealtimeSettings {
  gpu::DiSettings di;            // light_tiles.*, restir_di.* (and the keys GI shares)
  gpu::GiSettings gi;            // restir_gi.*, specular.*, brdf.* of the glossy paths
  gpu::WorldCacheSettings cache; // world_cache.* (and the light_tiles.*, brdf.*, specular.* it sees)
  // light_tiles.size_to_scene: fit_to_run sizes di.samples_per_tile to the scene's lights.
  bool size_light_tiles_to_scene{};
  // specular.di_handover_alpha: the primary alpha at or below which DI leaves
  // the specular lobe to specular GI. GI takes it when specular.enabled
  // (realtime_settings), DI when specular GI runs beside it (fit_to_run);
  // otherwise both keep "never" (DiSettings/GiSettings::specular_handover_alpha).
  float specular_handover_alpha{};
  // textures.normal_map_decode as a NORMAL_MAP_DECODE_* of
  // core/shared/texture_sampling.h (the realtime passes' normal maps).
  std::uint32_t normal_map_decode{};
  gpu::MotionVectors motion_vectors{};  // temporal.motion_vectors
  // brdf.model as a BRDF_* of core/shared/brdf.h, and as the profile names it.
  std::uint32_t brdf_model{};
  std::string brdf_model_name;
  bool brdf_fresnel_raw{};       // brdf.fresnel_argument "raw": BRDF_FRESNEL_RAW
  bool brdf_evaluate_clamp{};    // brdf.evaluate_clamp "max_zero": BRDF_EVALUATE_CLAMP
  // restir_gi.jacobian_reject as the profile writes it: the jacobian check's
  // limit (GiSettings::jacobian_reject is the shader's float).
  double jacobian_reject{};
  // scene.raytracing_mesh_removal "ignored" (before v0.19.1, #24764): an
  // entity whose RaytracingMesh3d was removed stays in the ray-traced scene
  // (replay/frame_loop.cpp).
  bool raytracing_mesh_removal_ignored{};
};

// Every key of the profile through the table (gpu/profile_keys.h
// resolve_solari_profile), then what follows from two keys together:
// GI's handover alpha where specular.enabled. InputError (the profile's file
// and /values/<key>) for a key the profile lacks, a wrong type or a value
// the table does not know; restir_gi.initial_samples outside 1..64 likewise.
RealtimeSettings realtime_settings(const Profile& profile);

// The settings as one run uses them: DI's light tiles sized to the scene
// (light_tiles.size_to_scene, gpu/passes/di_pipeline.h), DI's handover alpha
// where specular GI runs beside it (with_specular_gi; alone, DI shades the full
// BRDF), and `chains` independent DI and GI chains per pipeline.
void fit_to_run(RealtimeSettings& settings, const FlatInstances& scene, bool with_specular_gi, std::uint32_t chains);

// The profile's material model on the scene (brdf.model with its NaN flags
// brdf.fresnel_argument, brdf.evaluate_clamp), so the realtime passes and the
// references judged against them shade with the same material model.
void apply_material_model(Scene& scene, const RealtimeSettings& settings);

// For tools and tests that want one part without a run (each resolves the
// whole profile; a run builds RealtimeSettings once, replay/run_setup.h).
void apply_material_model(Scene& scene, const Profile& profile);
gpu::DiSettings di_settings_from_profile(const Profile& profile, const FlatInstances& scene, std::uint32_t chains,
                                         bool with_specular_gi);
gpu::GiSettings gi_settings_from_profile(const Profile& profile, std::uint32_t chains);
// The instrumentation flags (view, stats, root_frame) are the caller's.
gpu::WorldCacheSettings world_cache_settings_from_profile(const Profile& profile);

}  // namespace gi
