// The realtime mode's pass settings from a resolved profile (DESIGN §3).
#pragma once
#include <cstdint>

#include "core/profile.h"
#include "core/scene.h"
#include "core/scene_flatten.h"
#include "gpu/passes/restir_di_settings.h"
#include "gpu/passes/restir_gi_settings.h"
#include "gpu/passes/world_cache.h"

namespace gi {

// `chains` independent DI chains (2 when a reference check needs an honest
// noise estimate, replay/checks/realtime_reference_check.h). With specular GI
// running beside it, DI leaves the smoothest surfaces' specular lobe to it
// (specular.di_handover_alpha); alone it shades the full BRDF.
gpu::DiSettings di_settings_from_profile(const Profile& profile, const FlatInstances& scene, std::uint32_t chains,
                                         bool with_specular_gi);

// The world cache's constants (world_cache.*, and light_tiles.* for the radiance
// encoding its direct samples see); the instrumentation flags are the caller's.
gpu::WorldCacheSettings world_cache_settings_from_profile(const Profile& profile);

// The profile's textures.normal_map_decode as a NORMAL_MAP_DECODE_* of
// core/shared/texture_sampling.h (the realtime passes' normal maps).
std::uint32_t normal_map_decode_from_profile(const Profile& profile);

// The profile's brdf.model as a BRDF_* of core/shared/brdf.h.
std::uint32_t brdf_model_from_profile(const Profile& profile);

// The profile's brdf.model on the scene, so the realtime passes and the
// references judged against them shade with the same material model.
void apply_material_model(Scene& scene, const Profile& profile);

// ReSTIR GI and specular GI (restir_gi.*, specular.*, brdf.min_perceptual_roughness;
// the pixel-similarity constants are restir_di's, the ray length world_cache.gi_ray_tmax),
// `chains` as for DI.
gpu::GiSettings gi_settings_from_profile(const Profile& profile, std::uint32_t chains);

}  // namespace gi
