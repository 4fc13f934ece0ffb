#include "gpu/passes/restir_gi_settings.h"

#include <string>

#include <fmt/format.h>

namespace gi::gpu {

std::vector<ShaderDefine> GiSettings::defines() const {
  // Floats printed with enough digits to round-trip, as GLSL float literals.
  auto f = [](float v) {
    const std::string s = fmt::format("{:.9g}", v);
    return s.find_first_of(".e") == std::string::npos ? s + ".0" : s;
  };
  std::vector<ShaderDefine> d = {{"GI_CONFIDENCE_CAP", f(confidence_cap)},
          {"GI_SPATIAL_RADIUS", f(spatial_radius)},
          {"GI_SPATIAL_TRIES", std::to_string(spatial_tries) + "u"},
          {"GI_PLANE_TOLERANCE", f(plane_tolerance)},
          {"GI_NORMAL_MIN_DOT", f(normal_min_dot)},
          {"GI_JACOBIAN_REJECT", f(jacobian_reject)},
          {"GI_JACOBIAN_REJECTION", jacobian_rejection ? "1" : "0"},
          {"GI_JACOBIAN_BOTH", jacobian_both ? "1" : "0"},
          {"GI_TEMPORAL_PERMUTATION", temporal_permutation ? "1" : "0"},
          {"GI_TEMPORAL_FALLBACK", std::to_string(static_cast<int>(temporal_fallback))},
          {"GI_TEMPORAL_EDGE_STATS", temporal_edge_stats ? "1" : "0"},
          {"GI_PATH_COUNTERS", path_counters ? "1" : "0"},
          {"SPATIAL_RADIUS_HALVING", spatial_radius_halving ? "1" : "0"},
          {"SPATIAL_DISK_CLAMPED", spatial_disk_clamped ? "1" : "0"},
          {"GI_TARGET_BRDF", target_brdf ? "1" : "0"},
          {"GI_TEMPORAL_HISTORY", temporal_history_pre_spatial ? "1" : "0"},
          {"GI_EMPTY_NO_CONFIDENCE", empty_no_confidence ? "1" : "0"},
          {"GI_EMISSIVE_TEST", std::to_string(static_cast<int>(emissive_test))},
          {"GI_VISIBILITY_FINAL", visibility_final ? "1" : "0"},
          {"GI_VISIBILITY_FINAL_STORED", visibility_final && visibility_final_stored ? "1" : "0"},
          {"GI_COSINE_TWICE", cosine_twice ? "1" : "0"},
          {"GI_SHADING_DIFFUSE", shading_diffuse ? "1" : "0"},
          {"GI_SKIP_SMOOTH_METALS", skip_smooth_metals ? "1" : "0"},
          {"GI_OFFSCREEN_OWN_PIXEL", offscreen_own_pixel ? "1" : "0"},
          {"GI_SECONDARY_ALBEDO_BASE", secondary_albedo_base ? "1" : "0"},
          {"GI_HIT_CACHE_NORMAL_VERTEX", hit_cache_normal_vertex ? "1" : "0"},
          {"GI_SAMPLE_NORMAL_SHADING", sample_normal_shading ? "1" : "0"},
          {"GI_CONSISTENT_MIS", consistent_mis ? "1" : "0"},
          {"GI_HIT_RADIANCE", std::to_string(static_cast<int>(hit_radiance))},
          {"GI_SECONDARY_HITS_FULL", secondary_hits_full ? "1" : "0"},
          {"GI_RAY_TMAX", f(ray_tmax)},
          {"SPECULAR_REUSE_ROUGHNESS", f(specular_reuse_roughness)},
          {"SPECULAR_POWER_MIS", specular_power_mis ? "1" : "0"},
          {"SPECULAR_PATH_SPREAD", specular_path_spread ? "1" : "0"},
          {"SPECULAR_PATH_LONG_RAY", specular_path_long_ray ? "1" : "0"},
          {"SPECULAR_CACHE_EVERY_VERTEX", specular_cache_every_vertex ? "1" : "0"},
          {"SPECULAR_RUSSIAN_ROULETTE", specular_russian_roulette ? "1" : "0"},
          {"SPECULAR_MIS_LIGHT_PDF_AREA", specular_mis_light_pdf_area ? "1" : "0"},
          {"SPECULAR_MESH_TANGENT_FRAME", specular_mesh_tangent_frame ? "1" : "0"},
          {"SPECULAR_PERFECT_MIRROR_METAL", specular_perfect_mirror_metal ? "1" : "0"},
          {"SPECULAR_SUN_NEE_ONLY", specular_sun_nee_only ? "1" : "0"},
          {"SPECULAR_HANDOVER_ALPHA", f(specular_handover_alpha)},
          {"SPECULAR_MAX_BOUNCES", std::to_string(specular_max_bounces) + "u"},
          {"SPECULAR_MIN_PERCEPTUAL_ROUGHNESS", f(min_perceptual_roughness)}};
  if (!temporal_reuse) d.push_back({"GI_NO_TEMPORAL_REUSE", ""});
  // Only when not Solari's 1: the released variants keep their compiled shaders.
  if (initial_samples != 1) d.push_back({"GI_INITIAL_SAMPLES", std::to_string(initial_samples)});
  if (specular_mirror_exact) d.push_back({"SPECULAR_MIRROR_EXACT", "1"});
  if (specular_mirror_throughput_brdf) d.push_back({"SPECULAR_MIRROR_THROUGHPUT_BRDF", "1"});
  if (specular_vndf_mirror_alpha != 0.001f) d.push_back({"SPECULAR_VNDF_MIRROR_ALPHA", f(specular_vndf_mirror_alpha)});
  if (queries_world_cache()) d.insert(d.end(), world_cache_defines.begin(), world_cache_defines.end());
  return d;
}

}  // namespace gi::gpu
