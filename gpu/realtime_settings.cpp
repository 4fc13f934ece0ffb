#include "gpu/realtime_settings.h"

#include "core/shared/brdf.h"
#include "gpu/passes/di_pipeline.h"
#include "gpu/profile_keys.h"

namespace gi {

RealtimeSettings realtime_settings(const Profile& profile) {
  RealtimeSettings s = resolve_solari_profile(profile);
  // At a primary alpha at or below this the glossy path counts its first
  // hit's emission; with specular GI off GI keeps "never".
  if (s.gi.specular) s.gi.specular_handover_alpha = s.specular_handover_alpha;
  return s;
}

void fit_to_run(RealtimeSettings& s, const FlatInstances& scene, bool with_specular_gi, std::uint32_t chains) {
  if (s.size_light_tiles_to_scene)
    s.di.samples_per_tile = gpu::light_tile_samples_for_scene(scene, s.di.samples_per_tile, s.di.initial_samples);
  if (with_specular_gi) s.di.specular_handover_alpha = s.specular_handover_alpha;
  s.di.chains = chains;
  s.gi.chains = chains;
}

// The model with #24668's NaN flags above it (brdf.h): every material carries them.
void apply_material_model(Scene& scene, const RealtimeSettings& s) {
  scene.brdf_model = s.brdf_model;
  if (s.brdf_fresnel_raw) scene.brdf_model |= shader::BRDF_FRESNEL_RAW;
  if (s.brdf_evaluate_clamp) scene.brdf_model |= shader::BRDF_EVALUATE_CLAMP;
}

void apply_material_model(Scene& scene, const Profile& profile) {
  apply_material_model(scene, realtime_settings(profile));
}

gpu::DiSettings di_settings_from_profile(const Profile& profile, const FlatInstances& scene, std::uint32_t chains,
                                         bool with_specular_gi) {
  RealtimeSettings s = realtime_settings(profile);
  fit_to_run(s, scene, with_specular_gi, chains);
  return s.di;
}

gpu::GiSettings gi_settings_from_profile(const Profile& profile, std::uint32_t chains) {
  gpu::GiSettings gi = realtime_settings(profile).gi;
  gi.chains = chains;
  return gi;
}

gpu::WorldCacheSettings world_cache_settings_from_profile(const Profile& profile) {
  return realtime_settings(profile).cache;
}

}  // namespace gi
