#include "gpu/passes/restir_di_settings.h"

#include <fmt/format.h>

namespace gi::gpu {

std::vector<ShaderDefine> DiSettings::defines() const {
  // Floats printed with enough digits to round-trip, as GLSL float literals.
  auto f = [](float v) { return fmt::format("{:.9g}", v).find_first_of(".e") == std::string::npos
                                    ? fmt::format("{:.9g}.0", v)
                                    : fmt::format("{:.9g}", v); };
  std::vector<ShaderDefine> d = {{"LIGHT_TILE_COUNT", std::to_string(tile_count) + "u"},
          {"LIGHT_TILE_SAMPLES", std::to_string(samples_per_tile) + "u"},
          {"LIGHT_TILE_EXPOSURE", f(exposure)},
          {"LIGHT_TILE_LOG2_RADIANCE", log2_radiance ? "1" : "0"},
          {"LIGHT_TILE_SCROLLING", tile_seed_scrolling ? "1" : "0"},
          {"DI_INITIAL_SAMPLES", std::to_string(initial_samples) + "u"},
          {"DI_CONFIDENCE_CAP", f(confidence_cap)},
          {"DI_SPATIAL_RADIUS", f(spatial_radius)},
          {"DI_SPATIAL_TRIES", std::to_string(spatial_tries) + "u"},
          {"DI_PLANE_TOLERANCE", f(plane_tolerance)},
          {"DI_NORMAL_MIN_DOT", f(normal_min_dot)},
          {"DI_BALANCE_MIS", balance_mis ? "1" : "0"},
          {"DI_MIS_VISIBILITY", mis_visibility ? "1" : "0"},
          {"DI_TARGET_BASE_COLOR", target_base_color ? "1" : "0"},
          {"DI_TEMPORAL_PERMUTATION", temporal_permutation ? "1" : "0"},
          {"DI_TEMPORAL_FALLBACK", temporal_fallback ? "1" : "0"},
          {"DI_OFFSCREEN_OWN_PIXEL", offscreen_own_pixel ? "1" : "0"},
          {"DI_TILE_PER_WORKGROUP", tile_per_workgroup ? "1" : "0"},
          {"DI_VISIBILITY_FINAL", visibility_final ? "1" : "0"},
          {"DI_INITIAL_VISIBILITY", initial_visibility_fed_forward ? "1" : "0"},
          {"DI_REUSE_RADIANCE_SCENE", reuse_radiance_scene ? "1" : "0"},
          {"DI_SPECULAR_HANDOVER_ALPHA", f(specular_handover_alpha)},
          {"DI_SHADING_BASE_OVER_PI", shading_base_over_pi ? "1" : "0"},
          {"DI_EMISSIVE_UNEXPOSED", emissive_unexposed ? "1" : "0"},
          {"SPATIAL_RADIUS_HALVING", spatial_radius_halving ? "1" : "0"},
          {"SPATIAL_DISK_CLAMPED", spatial_disk_clamped ? "1" : "0"}};
  if (visibility_final && visibility_final_stored) d.push_back({"DI_VISIBILITY_FINAL_STORED", "1"});
  if (sun_center) d.push_back({"LIGHT_SUN_CENTER", "1"});
  if (traces_previous_scene()) d.push_back({"TRACE_PREVIOUS_SCENE", ""});
  if (show_background && background != glm::vec3(0.0f))
    d.push_back({"DI_BACKGROUND", fmt::format("vec3({},{},{})", f(background.x), f(background.y), f(background.z))});
  return d;
}

}  // namespace gi::gpu
