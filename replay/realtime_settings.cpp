#include "replay/realtime_settings.h"

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/errors.h"
#include "core/shared/brdf.h"
#include "gpu/passes/di_pipeline.h"

namespace gi {

gpu::DiSettings di_settings_from_profile(const Profile& p, const FlatInstances& scene, std::uint32_t chains,
                                         bool with_specular_gi) {
  gpu::DiSettings s;
  s.tile_count = static_cast<std::uint32_t>(p.integer("light_tiles.tile_count"));
  s.initial_samples = static_cast<std::uint32_t>(p.integer("restir_di.initial_samples"));
  s.samples_per_tile = static_cast<std::uint32_t>(p.integer("light_tiles.samples_per_tile"));
  if (p.flag("light_tiles.size_to_scene"))
    s.samples_per_tile = gpu::light_tile_samples_for_scene(scene, s.samples_per_tile, s.initial_samples);
  s.exposure = static_cast<float>(p.number("light_tiles.exposure"));
  s.log2_radiance = p.text("light_tiles.radiance_encoding") == "log2";
  s.tile_seed_scrolling = p.text("light_tiles.seeding") == "scrolling";
  s.confidence_cap = static_cast<float>(p.number("restir_di.confidence_cap"));
  s.spatial_radius = static_cast<float>(p.number("restir_di.spatial_radius_px"));
  s.spatial_tries = static_cast<std::uint32_t>(p.integer("restir_di.spatial_tries"));
  s.plane_tolerance = static_cast<float>(p.number("restir_di.dissimilar_plane_tolerance"));
  s.normal_min_dot = static_cast<float>(p.number("restir_di.dissimilar_normal_min_dot"));
  s.balance_mis = p.text("restir_di.mis") == "balance";
  s.mis_visibility = p.flag("restir_di.mis_visibility");
  s.mis_previous_scene = p.text("restir_di.temporal_mis_scene") == "previous_frame";
  s.target_base_color = p.text("restir_di.target") == "base_over_pi";
  s.temporal_permutation = p.flag("restir_di.temporal_permutation");
  s.temporal_fallback = p.text("restir_di.temporal_fallback") == "point";
  s.offscreen_own_pixel = p.text("restir_di.offscreen_reprojection") == "own_pixel";
  s.tile_per_workgroup = p.text("restir_di.tile_choice") == "workgroup";
  s.visibility_final = p.text("restir_di.visibility") != "spatial_fed_forward";
  s.visibility_final_stored = p.text("restir_di.visibility") == "final_stored";
  s.initial_visibility_fed_forward = p.text("restir_di.initial_visibility") == "fed_forward";
  s.shading_base_over_pi = p.text("restir_di.shading") == "base_over_pi";
  s.emissive_unexposed = p.text("restir_di.emissive_exposure") == "unexposed";
  s.sun_center = p.text("light_tiles.sun_sampling") == "center";
  s.show_background = p.text("restir_di.background") == "clear_color";
  s.spatial_radius_halving = p.text("restir_di.spatial_search") == "halving";
  s.chains = chains;
  if (with_specular_gi) s.specular_handover_alpha = static_cast<float>(p.number("specular.di_handover_alpha"));
  return s;
}

std::uint32_t normal_map_decode_from_profile(const Profile& p) {
  const std::string& decode = p.text("textures.normal_map_decode");
  if (decode == "raw") return shader::NORMAL_MAP_DECODE_RAW;
  if (decode == "none") return shader::NORMAL_MAP_DECODE_NONE;
  return shader::NORMAL_MAP_DECODE_SIGNED;
}

std::uint32_t brdf_model_from_profile(const Profile& p) {
  const std::string& model = p.text("brdf.model");
  if (model == "multiscatter_approx") return shader::BRDF_MULTISCATTER_APPROX;
  if (model == "layered_polynomial") return shader::BRDF_LAYERED_POLYNOMIAL;
  if (model == "layered") return shader::BRDF_LAYERED;
  if (model == "lobes_blended_f0") return shader::BRDF_LOBES_BLENDED_F0;
  if (model == "lobes") return shader::BRDF_LOBES;
  return shader::BRDF_SINGLE_SCATTER;
}

// The model with #24668's NaN flags above it (brdf.h): every material carries them.
void apply_material_model(Scene& scene, const Profile& p) {
  scene.brdf_model = brdf_model_from_profile(p);
  if (p.text("brdf.fresnel_argument") == "raw") scene.brdf_model |= shader::BRDF_FRESNEL_RAW;
  if (p.text("brdf.evaluate_clamp") == "max_zero") scene.brdf_model |= shader::BRDF_EVALUATE_CLAMP;
}

gpu::WorldCacheSettings world_cache_settings_from_profile(const Profile& p) {
  gpu::WorldCacheSettings s;
  s.cells = static_cast<std::uint32_t>(p.integer("world_cache.cells"));
  s.lifetime = static_cast<std::uint32_t>(p.integer("world_cache.lifetime"));
  s.max_probe_steps = static_cast<std::uint32_t>(p.integer("world_cache.max_probe_steps"));
  s.linear_probing = p.text("world_cache.probing") == "linear";
  s.cell_size_base = static_cast<float>(p.number("world_cache.cell_size_base"));
  s.lod_scale = static_cast<float>(p.number("world_cache.lod_scale"));
  s.stochastic_lod = p.text("world_cache.lod_choice") == "stochastic";
  s.jitter = p.text("world_cache.query_jitter") == "tangent_plane";
  s.jitter_lod_redrawn = p.text("world_cache.jitter_lod") == "redrawn";
  s.normal_key_scale = p.text("world_cache.normal_key") == "half_unit" ? 2.0f : 1.0f;
  s.first_bounce_leak_rule = p.flag("world_cache.first_bounce_leak_rule");
  s.update_soft_cap = static_cast<std::uint32_t>(p.integer("world_cache.update_soft_cap"));
  s.update_workgroup_size = static_cast<std::uint32_t>(p.integer("world_cache.workgroup_size"));
  s.cache_to_cache_full = p.text("world_cache.cache_to_cache_life") == "full";
  s.adaptive_blend = p.text("world_cache.blend") == "adaptive";
  s.max_samples = static_cast<float>(p.number("world_cache.max_samples"));
  s.adaptive_exponent = static_cast<float>(p.number("world_cache.adaptive_exponent"));
  s.delta_blend = static_cast<float>(p.number("world_cache.delta_blend"));
  s.di_samples = static_cast<std::uint32_t>(p.integer("world_cache.di_samples"));
  s.gi_ray_tmax = static_cast<float>(p.number("world_cache.gi_ray_tmax"));
  s.gi_reach_cosine = p.text("world_cache.gi_ray_direction") == "unnormalised";
  s.light_exposure = static_cast<float>(p.number("light_tiles.exposure"));
  s.log2_radiance = p.text("light_tiles.radiance_encoding") == "log2";
  s.secondary_hits_full = p.text("brdf.secondary_hits") == "full";
  s.secondary_albedo_base = p.text("brdf.secondary_albedo") == "base_color";
  s.drop_zero_channel_light = p.text("world_cache.direct_light_zero_channel") == "drop";
  s.direct_light_cosine_missing = p.text("world_cache.direct_light_cosine") == "missing";
  s.sun_center = p.text("light_tiles.sun_sampling") == "center";
  s.tile_candidates = p.text("world_cache.direct_light_candidates") == "light_tiles";
  s.tiles_previous_frame = p.text("world_cache.light_tiles_frame") == "previous";
  s.glossy_roughness = static_cast<float>(p.number("specular.reuse_gi_roughness"));
  s.glossy_bounces = static_cast<std::uint32_t>(p.integer("specular.max_bounces"));
  return s;
}

namespace {

// The enum value a string key names. Profiles are validated against their
// "allowed" lists on load, so an unlisted value here is a programming error.
template <class E>
E choice(const Profile& p, const std::string& key, std::initializer_list<std::pair<const char*, E>> values) {
  const std::string& v = p.text(key);
  for (const auto& [name, e] : values)
    if (v == name) return e;
  throw std::logic_error("profile key " + key + ": no setting for \"" + v + "\"");
}

}  // namespace

gpu::GiSettings gi_settings_from_profile(const Profile& p, std::uint32_t chains) {
  using G = gpu::GiSettings;
  gpu::GiSettings s;
  s.confidence_cap = static_cast<float>(p.number("restir_gi.confidence_cap"));
  const long long initial = p.integer("restir_gi.initial_samples");
  if (initial < 1 || initial > 64)
    throw InputError("profile " + p.name, "restir_gi.initial_samples", "an integer from 1 to 64, got " + std::to_string(initial));
  s.initial_samples = static_cast<std::uint32_t>(initial);
  s.spatial_radius = static_cast<float>(p.number("restir_gi.spatial_radius_px"));
  s.spatial_tries = static_cast<std::uint32_t>(p.integer("restir_di.spatial_tries"));
  s.spatial_radius_halving = p.text("restir_di.spatial_search") == "halving";
  s.plane_tolerance = static_cast<float>(p.number("restir_di.dissimilar_plane_tolerance"));
  s.normal_min_dot = static_cast<float>(p.number("restir_di.dissimilar_normal_min_dot"));
  s.jacobian_reject = static_cast<float>(p.number("restir_gi.jacobian_reject"));
  s.jacobian_rejection = p.flag("restir_gi.jacobian_rejection");
  s.jacobian_both = p.text("restir_gi.jacobian_rejection_directions") == "both";
  s.temporal_permutation = p.flag("restir_gi.temporal_permutation");
  s.temporal_reuse = p.flag("restir_gi.temporal_reuse");
  s.temporal_fallback = choice<G::TemporalFallback>(p, "restir_gi.temporal_fallback",
                                                    {{"point", G::TemporalFallback::point},
                                                     {"retry", G::TemporalFallback::retry},
                                                     {"none", G::TemporalFallback::none}});
  s.target_brdf = p.text("restir_gi.target") == "base_over_pi";
  s.temporal_history_pre_spatial = p.text("restir_gi.temporal_history") == "temporal";
  s.empty_no_confidence = p.text("restir_gi.empty_samples") == "no_confidence";
  s.emissive_test = choice<G::EmissiveTest>(p, "restir_gi.emissive_hit_test",
                                            {{"all_channels", G::EmissiveTest::all_channels},
                                             {"any_channel", G::EmissiveTest::any_channel},
                                             {"front_any_channel", G::EmissiveTest::front_any_channel}});
  s.visibility_final = p.text("restir_gi.visibility") != "spatial_fed_forward";
  s.visibility_final_stored = p.text("restir_gi.visibility") == "final_stored";
  s.cosine_twice = p.text("restir_gi.shading_cosine") == "twice";
  s.shading_diffuse = p.text("restir_gi.diffuse_shading") == "diffuse";
  s.skip_smooth_metals = p.text("restir_gi.smooth_metals") == "skip";
  s.offscreen_own_pixel = p.text("restir_di.offscreen_reprojection") == "own_pixel";
  s.secondary_albedo_base = p.text("brdf.secondary_albedo") == "base_color";
  s.consistent_mis = p.text("restir_gi.mis_weights") == "consistent";
  s.hit_radiance = choice<G::HitRadiance>(p, "restir_gi.hit_radiance",
                                          {{"nee", G::HitRadiance::nee},
                                           {"world_cache", G::HitRadiance::world_cache},
                                           {"path", G::HitRadiance::path}});
  s.ray_tmax = static_cast<float>(p.number("restir_gi.ray_tmax"));
  s.specular = p.flag("specular.enabled");
  s.specular_reuse_roughness = static_cast<float>(p.number("specular.reuse_gi_roughness"));
  s.specular_max_bounces = static_cast<std::uint32_t>(p.integer("specular.max_bounces"));
  s.specular_power_mis = p.text("specular.mis") == "power";
  s.specular_path_spread = p.text("specular.path_end") == "path_spread";
  s.specular_path_long_ray = p.text("specular.path_end") == "long_ray_rough_path";
  s.specular_cache_every_vertex = p.text("specular.path_end") == "cache_every_vertex";
  s.specular_russian_roulette = p.flag("specular.russian_roulette");
  s.specular_vndf_mirror_alpha = static_cast<float>(p.number("specular.vndf_mirror_alpha"));
  s.specular_mis_light_pdf_area = p.text("specular.mis_light_pdf") == "area";
  s.specular_mirror_exact = p.text("brdf.mirror") == "exact";
  s.specular_mesh_tangent_frame = p.text("brdf.sampling_frame") == "mikktspace";
  s.specular_perfect_mirror_metal = p.text("specular.perfect_mirror") == "alpha_and_metallic";
  s.specular_sun_nee_only = p.text("specular.directional_lights") == "nee_only";
  if (s.specular) s.specular_handover_alpha = static_cast<float>(p.number("specular.di_handover_alpha"));
  s.min_perceptual_roughness = static_cast<float>(p.number("brdf.min_perceptual_roughness"));
  s.secondary_hits_full = p.text("brdf.secondary_hits") == "full";
  s.chains = chains;
  return s;
}

}  // namespace gi
