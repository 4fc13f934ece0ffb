// The realtime mode's pass settings from a resolved profile (DESIGN §3).
#pragma once
#include <cstdint>

#include "core/profile.h"
#include "core/scene_flatten.h"
#include "gpu/passes/restir_di_settings.h"

namespace gi {

// `chains` independent DI chains (2 when a reference check needs an honest
// noise estimate, replay/checks/realtime_reference_check.h).
gpu::DiSettings di_settings_from_profile(const Profile& profile, const FlatInstances& scene, std::uint32_t chains);

}  // namespace gi
