// The profile table: every key of the released profiles, once, with its type,
// its values and the settings fields it fills (gpu/profile_keys.h). The key
// strings below are their only appearance in C++ (tests/profile_keys_test.cpp
// greps core/, gpu/, reports/, checks/, replay/ and app/ for them).
//
// A row reads (restir_gi.confidence_cap's, with the key in quotes):
//   number(<key>, to(&S::gi, &Gi::confidence_cap))
//   integer / number / flag: the value converted to each field's type;
//   choice<T>: every string the key may take, each with the T it stands for;
//   several to(...): the one value copied into each (a key DI and GI share);
//   a lambda (S&, const T&): a value that fills more than one field its own way;
//   integer_in: refused outside its range; integer_clamped: clamped into it;
//   recorded: a key summary.json records and no setting reads.
//
// Adding a profile switch, from JSON to shader:
//   1. scenarios/profiles/solari-0.17.json, -0.18.json, -0.19.json: the key in
//      each, its "value" and its "source" (the Bevy lines it follows, cited per
//      core/bevy_citation.h), "allowed" for a string (every value, the same list
//      in the three files);
//   2. one row here, in its group (the key, its type, every allowed value with
//      the C++ value it maps to, the field it fills);
//   3. the field in the settings struct (gpu/passes/restir_di_settings.h,
//      restir_gi_settings.h, world_cache.h, or RealtimeSettings in
//      gpu/realtime_settings.h for what no pass compiles), value-initialised
//      (`bool my_switch{};`): the value is the profile's, never a second one here;
//   4. its #define in that struct's defines() (gpu/passes/*_settings.cpp,
//      WorldCacheSettings::defines in world_cache.cpp);
//   5. the shader reads the define (gpu/shaders/, core/shared/).
// tests/profile_keys_test.cpp fails until 1 and 2 agree (keys, types, values).
#include "gpu/profile_keys.h"

#include <algorithm>
#include <functional>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/scenario.h"  // json_pointer_token
#include "core/shared/brdf.h"
#include "core/shared/rc/cascades.h"
#include "core/shared/texture_sampling.h"
#include "gpu/realtime_settings.h"

namespace gi {
namespace {

using nlohmann::json;
using S = RealtimeSettings;
using Di = gpu::DiSettings;
using Gi = gpu::GiSettings;
using Wc = gpu::WorldCacheSettings;
using Rc = RcSettings;

// ---- The machinery ----

template <class Target>
const Target& probe() {
  static const Target t{};
  return t;
}

template <class Target>
constexpr ProfileFamily family_of() {
  return std::is_same_v<Target, Rc> ? ProfileFamily::radiance_cascades : ProfileFamily::solari;
}

// A field of Target a row fills, and where it lies (for profile_key_of).
template <class Target, class F>
struct Field {
  std::function<F&(Target&)> at;
  std::size_t offset;
};

std::size_t offset_in(const void* field, const void* base) {
  return static_cast<std::size_t>(static_cast<const char*>(field) - static_cast<const char*>(base));
}

template <class Target, class F>
Field<Target, F> to(F Target::*member) {
  const Target& p = probe<Target>();
  return {[member](Target& t) -> F& { return t.*member; }, offset_in(&(p.*member), &p)};
}

template <class Target, class Part, class F>
Field<Target, F> to(Part Target::*part, F Part::*member) {
  const Target& p = probe<Target>();
  return {[part, member](Target& t) -> F& { return (t.*part).*member; }, offset_in(&((p.*part).*member), &p)};
}

// A choice's value as the profile names it (its_name(to(...)): a string field).
template <class Target>
struct NameField {
  Field<Target, std::string> field;
};
template <class Target>
NameField<Target> its_name(Field<Target, std::string> f) {
  return {std::move(f)};
}

template <class T>
struct is_field : std::false_type {};
template <class Target, class F>
struct is_field<Field<Target, F>> : std::true_type {};
template <class T>
struct is_name_field : std::false_type {};
template <class Target>
struct is_name_field<NameField<Target>> : std::true_type {};

// A choice row's value: the V its string stands for, and the string.
template <class V>
struct Chosen {
  V value;
  std::string name;
};
template <class V>
const V& value_of(const V& v) {
  return v;
}
template <class V>
const V& value_of(const Chosen<V>& v) {
  return v.value;
}

template <class Target>
struct Row {
  ProfileKeyInfo info;
  std::function<void(Target&, const json&, const Profile&)> fill;  // the value's type already checked
  std::vector<std::size_t> offsets;                                // the to(...) fields it fills
};

template <class Target, class V>
using Setter = std::function<void(Target&, const V&)>;

template <class Target, class V, class D>
void add_destination(Row<Target>& row, std::vector<Setter<Target, V>>& sets, D d) {
  if constexpr (is_name_field<D>::value) {
    row.offsets.push_back(d.field.offset);
    sets.push_back([at = d.field.at](Target& t, const V& v) { at(t) = v.name; });
  } else if constexpr (is_field<D>::value) {
    row.offsets.push_back(d.offset);
    sets.push_back([at = d.at](Target& t, const V& v) {
      auto& f = at(t);
      f = static_cast<std::remove_reference_t<decltype(f)>>(value_of(v));
    });
  } else {
    sets.push_back([d](Target& t, const V& v) { d(t, value_of(v)); });
  }
}

// `read` turns the profile's JSON value (of the row's type) into a V.
template <class Target, class V, class... D>
Row<Target> make_row(const char* key, ProfileKeyType type, std::vector<std::string> choices,
                     std::function<V(const json&, const Profile&)> read, D... destinations) {
  Row<Target> row;
  row.info = {key, type, family_of<Target>(), std::move(choices), {}};
  std::vector<Setter<Target, V>> sets;
  (add_destination<Target, V>(row, sets, destinations), ...);
  row.fill = [read = std::move(read), sets = std::move(sets)](Target& t, const json& j, const Profile& p) {
    const V v = read(j, p);
    for (const auto& set : sets) set(t, v);
  };
  return row;
}

template <class Target = S, class... D>
Row<Target> integer(const char* key, D... d) {
  return make_row<Target, long long>(key, ProfileKeyType::integer, {},
                                     [](const json& j, const Profile&) { return j.get<long long>(); }, d...);
}

// Refused outside lo..hi: InputError("profile <name>", key).
template <class Target = S, class... D>
Row<Target> integer_in(const char* key, long long lo, long long hi, D... d) {
  const std::string k = key;
  return make_row<Target, long long>(
      key, ProfileKeyType::integer, {},
      [k, lo, hi](const json& j, const Profile& p) {
        const long long v = j.get<long long>();
        if (v < lo || v > hi)
          throw InputError("profile " + p.name, k, fmt::format("an integer from {} to {}, got {}", lo, hi, v));
        return v;
      },
      d...);
}

// Clamped into lo..hi (counts the passes can hold).
template <class Target = S, class... D>
Row<Target> integer_clamped(const char* key, long long lo, long long hi, D... d) {
  return make_row<Target, long long>(
      key, ProfileKeyType::integer, {},
      [lo, hi](const json& j, const Profile&) { return std::clamp<long long>(j.get<long long>(), lo, hi); }, d...);
}

template <class Target = S, class... D>
Row<Target> number(const char* key, D... d) {
  return make_row<Target, double>(key, ProfileKeyType::number, {},
                                  [](const json& j, const Profile&) { return j.get<double>(); }, d...);
}

template <class Target = S, class... D>
Row<Target> flag(const char* key, D... d) {
  return make_row<Target, bool>(key, ProfileKeyType::flag, {},
                                [](const json& j, const Profile&) { return j.get<bool>(); }, d...);
}

// Every value the key may take, each with the V it stands for. A value the
// row lacks (a profile file of one's own) is refused at /values/<key>/value.
template <class V, class Target = S, class... D>
Row<Target> choice(const char* key, std::vector<std::pair<std::string, V>> values, D... d) {
  std::vector<std::string> names;
  for (const auto& [name, _] : values) names.push_back(name);
  const std::string k = key;
  return make_row<Target, Chosen<V>>(
      key, ProfileKeyType::choice, names,
      [k, values = std::move(values), names](const json& j, const Profile& p) {
        const std::string& v = j.get_ref<const std::string&>();
        for (const auto& [name, value] : values)
          if (name == v) return Chosen<V>{value, name};
        std::string list;
        for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
        throw InputError(p.file.string(), "/values/" + json_pointer_token(k) + "/value",
                         fmt::format("one of {} (the values gpu/profile_keys.cpp knows), got \"{}\"", list, v));
      },
      d...);
}

// A key no setting reads: its type is checked, summary.json records it.
Row<S> recorded(const char* key, ProfileKeyType type, const char* why) {
  Row<S> row;
  row.info = {key, type, ProfileFamily::solari, {}, why};
  row.fill = [](S&, const json&, const Profile&) {};
  return row;
}

// restir_di.visibility, restir_gi.visibility: the final ray, and whether it
// is stored.
struct Visibility {
  bool final_ray, stored;
};
// specular.path_end: where a glossy path ends in the cache.
struct PathEnd {
  bool spread, long_ray, every_vertex;
};

// ---- The table: the Solari profiles (RealtimeSettings) ----

const std::vector<Row<S>>& solari_rows() {
  static const std::vector<Row<S>> rows = [] {
    std::vector<Row<S>> r;
    auto add = [&](Row<S> row) { r.push_back(std::move(row)); };

    // The scene, the G-buffer, textures and visibility IDs.
    add(choice<bool>("scene.raytracing_mesh_removal", {{"ignored", true}, {"applied", false}},
                     to(&S::raytracing_mesh_removal_ignored)));
    add(choice<gpu::MotionVectors>("temporal.motion_vectors",
                                   {{"object", gpu::MotionVectors::object},
                                    {"camera", gpu::MotionVectors::camera},
                                    {"ignored", gpu::MotionVectors::ignored}},
                                   to(&S::motion_vectors)));
    add(choice<std::uint32_t>("textures.normal_map_decode",
                              {{"raw", shader::NORMAL_MAP_DECODE_RAW},
                               {"signed", shader::NORMAL_MAP_DECODE_SIGNED},
                               {"none", shader::NORMAL_MAP_DECODE_NONE}},
                              to(&S::normal_map_decode)));
    add(recorded("visibility.cluster_id_bits", ProfileKeyType::integer,
                 "Bevy's meshlet visibility buffer, not Solari: the cluster_ids check has its own cluster_bits"));
    add(recorded("visibility.triangle_id_bits", ProfileKeyType::integer,
                 "Bevy's meshlet visibility buffer, not Solari"));

    // The material model (brdf.*).
    add(choice<std::uint32_t>("brdf.model",
                              {{"single_scatter", shader::BRDF_SINGLE_SCATTER},
                               {"multiscatter_approx", shader::BRDF_MULTISCATTER_APPROX},
                               {"layered_polynomial", shader::BRDF_LAYERED_POLYNOMIAL},
                               {"layered", shader::BRDF_LAYERED},
                               {"lobes_blended_f0", shader::BRDF_LOBES_BLENDED_F0},
                               {"lobes", shader::BRDF_LOBES}},
                              to(&S::brdf_model), its_name(to(&S::brdf_model_name))));
    add(choice<bool>("brdf.fresnel_argument", {{"saturated", false}, {"raw", true}}, to(&S::brdf_fresnel_raw)));
    add(choice<bool>("brdf.evaluate_clamp", {{"none", false}, {"max_zero", true}}, to(&S::brdf_evaluate_clamp)));
    add(choice<bool>("brdf.secondary_albedo", {{"base_color", true}, {"diffuse", false}},
                     to(&S::gi, &Gi::secondary_albedo_base), to(&S::cache, &Wc::secondary_albedo_base)));
    add(choice<bool>("brdf.secondary_hits", {{"diffuse", false}, {"full", true}},
                     to(&S::gi, &Gi::secondary_hits_full), to(&S::cache, &Wc::secondary_hits_full)));
    add(number("brdf.min_perceptual_roughness", to(&S::gi, &Gi::min_perceptual_roughness)));
    add(choice<bool>("brdf.mirror", {{"clamped_ggx", false}, {"exact", true}}, to(&S::gi, &Gi::specular_mirror_exact)));
    add(choice<bool>("brdf.sampling_frame", {{"mikktspace", true}, {"orthonormal", false}},
                     to(&S::gi, &Gi::specular_mesh_tangent_frame)));

    // Light tiles (DI's, and the world cache's direct-light candidates).
    add(integer("light_tiles.tile_count", to(&S::di, &Di::tile_count), to(&S::cache, &Wc::tile_count)));
    add(integer("light_tiles.samples_per_tile", to(&S::di, &Di::samples_per_tile), to(&S::cache, &Wc::tile_samples)));
    add(flag("light_tiles.size_to_scene", to(&S::size_light_tiles_to_scene)));
    add(number("light_tiles.exposure", to(&S::di, &Di::exposure), to(&S::cache, &Wc::light_exposure)));
    add(choice<bool>("light_tiles.radiance_encoding", {{"log2", true}, {"plain", false}},
                     to(&S::di, &Di::log2_radiance), to(&S::cache, &Wc::log2_radiance)));
    add(choice<bool>("light_tiles.seeding", {{"independent", false}, {"scrolling", true}},
                     to(&S::di, &Di::tile_seed_scrolling)));
    add(choice<bool>("light_tiles.sun_sampling", {{"cone", false}, {"center", true}}, to(&S::di, &Di::sun_center),
                     to(&S::cache, &Wc::sun_center)));

    // ReSTIR DI (its pixel-similarity rules, spatial search and off-screen
    // reprojection are GI's too).
    add(integer("restir_di.initial_samples", to(&S::di, &Di::initial_samples)));
    add(number("restir_di.confidence_cap", to(&S::di, &Di::confidence_cap)));
    add(number("restir_di.spatial_radius_px", to(&S::di, &Di::spatial_radius)));
    add(integer("restir_di.spatial_tries", to(&S::di, &Di::spatial_tries), to(&S::gi, &Gi::spatial_tries)));
    add(choice<bool>("restir_di.spatial_search", {{"fixed", false}, {"halving", true}},
                     to(&S::di, &Di::spatial_radius_halving), to(&S::gi, &Gi::spatial_radius_halving)));
    add(choice<bool>("restir_di.spatial_disk", {{"concentric_clamped", true}, {"polar_rejected", false}},
                     to(&S::di, &Di::spatial_disk_clamped), to(&S::gi, &Gi::spatial_disk_clamped)));
    add(number("restir_di.dissimilar_plane_tolerance", to(&S::di, &Di::plane_tolerance),
               to(&S::gi, &Gi::plane_tolerance)));
    add(number("restir_di.dissimilar_normal_min_dot", to(&S::di, &Di::normal_min_dot),
               to(&S::gi, &Gi::normal_min_dot)));
    add(choice<bool>("restir_di.offscreen_reprojection", {{"none", false}, {"own_pixel", true}},
                     to(&S::di, &Di::offscreen_own_pixel), to(&S::gi, &Gi::offscreen_own_pixel)));
    add(choice<bool>("restir_di.mis", {{"balance", true}, {"constant", false}}, to(&S::di, &Di::balance_mis)));
    add(flag("restir_di.mis_visibility", to(&S::di, &Di::mis_visibility)));
    add(choice<bool>("restir_di.temporal_mis_scene", {{"current", false}, {"previous_frame", true}},
                     to(&S::di, &Di::mis_previous_scene)));
    add(choice<bool>("restir_di.target", {{"base_over_pi", true}, {"diffuse_brdf", false}},
                     to(&S::di, &Di::target_base_color)));
    add(flag("restir_di.temporal_permutation", to(&S::di, &Di::temporal_permutation)));
    add(choice<bool>("restir_di.temporal_fallback", {{"none", false}, {"point", true}},
                     to(&S::di, &Di::temporal_fallback)));
    add(choice<bool>("restir_di.tile_choice", {{"workgroup", true}, {"pixel", false}},
                     to(&S::di, &Di::tile_per_workgroup)));
    add(choice<Visibility>("restir_di.visibility",
                           {{"final", {true, false}}, {"spatial_fed_forward", {false, false}},
                            {"final_stored", {true, true}}},
                           [](S& s, const Visibility& v) {
                             s.di.visibility_final = v.final_ray;
                             s.di.visibility_final_stored = v.stored;
                           }));
    add(choice<bool>("restir_di.initial_visibility", {{"fed_forward", true}, {"shading_only", false}},
                     to(&S::di, &Di::initial_visibility_fed_forward)));
    add(choice<bool>("restir_di.reuse_radiance", {{"scene", true}, {"tile_encoding", false}},
                     to(&S::di, &Di::reuse_radiance_scene)));
    add(choice<bool>("restir_di.shading", {{"base_over_pi", true}, {"brdf", false}},
                     to(&S::di, &Di::shading_base_over_pi)));
    add(choice<bool>("restir_di.emissive_exposure", {{"exposed", false}, {"unexposed", true}},
                     to(&S::di, &Di::emissive_unexposed)));
    add(choice<bool>("restir_di.background", {{"clear_color", true}, {"black", false}},
                     to(&S::di, &Di::show_background)));

    // ReSTIR GI.
    add(number("restir_gi.confidence_cap", to(&S::gi, &Gi::confidence_cap)));
    add(integer_in("restir_gi.initial_samples", 1, 64, to(&S::gi, &Gi::initial_samples)));
    add(number("restir_gi.spatial_radius_px", to(&S::gi, &Gi::spatial_radius)));
    add(number("restir_gi.jacobian_reject", to(&S::gi, &Gi::jacobian_reject), to(&S::jacobian_reject)));
    add(flag("restir_gi.jacobian_rejection", to(&S::gi, &Gi::jacobian_rejection)));
    add(choice<bool>("restir_gi.jacobian_rejection_directions", {{"one", false}, {"both", true}},
                     to(&S::gi, &Gi::jacobian_both)));
    add(flag("restir_gi.temporal_permutation", to(&S::gi, &Gi::temporal_permutation)));
    add(flag("restir_gi.temporal_reuse", to(&S::gi, &Gi::temporal_reuse)));
    add(choice<Gi::TemporalFallback>("restir_gi.temporal_fallback",
                                     {{"point", Gi::TemporalFallback::point},
                                      {"retry", Gi::TemporalFallback::retry},
                                      {"none", Gi::TemporalFallback::none}},
                                     to(&S::gi, &Gi::temporal_fallback)));
    add(choice<bool>("restir_gi.target", {{"base_over_pi", true}, {"radiance_cos", false}},
                     to(&S::gi, &Gi::target_brdf)));
    add(choice<bool>("restir_gi.temporal_history", {{"spatial", false}, {"temporal", true}},
                     to(&S::gi, &Gi::temporal_history_pre_spatial)));
    add(choice<bool>("restir_gi.empty_samples", {{"no_confidence", true}, {"count", false}},
                     to(&S::gi, &Gi::empty_no_confidence)));
    add(choice<Gi::EmissiveTest>("restir_gi.emissive_hit_test",
                                 {{"all_channels", Gi::EmissiveTest::all_channels},
                                  {"any_channel", Gi::EmissiveTest::any_channel},
                                  {"front_any_channel", Gi::EmissiveTest::front_any_channel}},
                                 to(&S::gi, &Gi::emissive_test)));
    add(choice<Visibility>("restir_gi.visibility",
                           {{"final", {true, false}}, {"spatial_fed_forward", {false, false}},
                            {"final_stored", {true, true}}},
                           [](S& s, const Visibility& v) {
                             s.gi.visibility_final = v.final_ray;
                             s.gi.visibility_final_stored = v.stored;
                           }));
    add(choice<bool>("restir_gi.shading_cosine", {{"once", false}, {"twice", true}}, to(&S::gi, &Gi::cosine_twice)));
    add(choice<bool>("restir_gi.diffuse_shading", {{"base_over_pi", false}, {"diffuse", true}},
                     to(&S::gi, &Gi::shading_diffuse)));
    add(choice<bool>("restir_gi.smooth_metals", {{"run", false}, {"skip", true}},
                     to(&S::gi, &Gi::skip_smooth_metals)));
    add(choice<bool>("restir_gi.mis_weights", {{"solari", false}, {"consistent", true}},
                     to(&S::gi, &Gi::consistent_mis)));
    add(choice<Gi::HitRadiance>("restir_gi.hit_radiance",
                                {{"path", Gi::HitRadiance::path},
                                 {"nee", Gi::HitRadiance::nee},
                                 {"world_cache", Gi::HitRadiance::world_cache}},
                                to(&S::gi, &Gi::hit_radiance)));
    add(number("restir_gi.ray_tmax", to(&S::gi, &Gi::ray_tmax)));
    add(choice<bool>("restir_gi.sample_normal", {{"shading", true}, {"face_toward_ray", false}},
                     to(&S::gi, &Gi::sample_normal_shading)));

    // Specular GI (glossy paths: GI's, and the world cache's secondary hits).
    add(flag("specular.enabled", to(&S::gi, &Gi::specular)));
    add(number("specular.reuse_gi_roughness", to(&S::gi, &Gi::specular_reuse_roughness),
               to(&S::cache, &Wc::glossy_roughness)));
    add(integer("specular.max_bounces", to(&S::gi, &Gi::specular_max_bounces), to(&S::cache, &Wc::glossy_bounces)));
    add(number("specular.di_handover_alpha", to(&S::specular_handover_alpha)));
    add(choice<bool>("specular.mis", {{"power", true}, {"balance", false}}, to(&S::gi, &Gi::specular_power_mis)));
    add(choice<PathEnd>("specular.path_end",
                        {{"long_ray_rough_path", {false, true, false}},
                         {"path_spread", {true, false, false}},
                         {"roughness", {false, false, false}},
                         {"cache_every_vertex", {false, false, true}}},
                        [](S& s, const PathEnd& e) {
                          s.gi.specular_path_spread = e.spread;
                          s.gi.specular_path_long_ray = e.long_ray;
                          s.gi.specular_cache_every_vertex = e.every_vertex;
                        }));
    add(flag("specular.russian_roulette", to(&S::gi, &Gi::specular_russian_roulette)));
    add(number("specular.vndf_mirror_alpha", to(&S::gi, &Gi::specular_vndf_mirror_alpha)));
    add(choice<bool>("specular.mis_light_pdf", {{"area", true}, {"solid_angle", false}},
                     to(&S::gi, &Gi::specular_mis_light_pdf_area)));
    add(choice<bool>("specular.perfect_mirror", {{"alpha_and_metallic", true}, {"alpha", false}},
                     to(&S::gi, &Gi::specular_perfect_mirror_metal)));
    add(choice<bool>("specular.directional_lights", {{"nee_only", true}, {"mis", false}},
                     to(&S::gi, &Gi::specular_sun_nee_only)));
    add(choice<bool>("specular.mirror_throughput", {{"sampled", false}, {"full_brdf", true}},
                     to(&S::gi, &Gi::specular_mirror_throughput_brdf)));

    // The world cache.
    add(integer("world_cache.cells", to(&S::cache, &Wc::cells)));
    add(integer("world_cache.lifetime", to(&S::cache, &Wc::lifetime)));
    add(integer("world_cache.max_probe_steps", to(&S::cache, &Wc::max_probe_steps)));
    add(choice<bool>("world_cache.probing", {{"linear", true}, {"rehash", false}}, to(&S::cache, &Wc::linear_probing)));
    add(number("world_cache.cell_size_base", to(&S::cache, &Wc::cell_size_base)));
    add(number("world_cache.lod_scale", to(&S::cache, &Wc::lod_scale)));
    add(choice<bool>("world_cache.lod_choice", {{"floor", false}, {"stochastic", true}},
                     to(&S::cache, &Wc::stochastic_lod)));
    add(choice<bool>("world_cache.query_jitter", {{"none", false}, {"tangent_plane", true}}, to(&S::cache, &Wc::jitter)));
    add(choice<bool>("world_cache.jitter_lod", {{"kept", false}, {"redrawn", true}},
                     to(&S::cache, &Wc::jitter_lod_redrawn)));
    add(choice<float>("world_cache.normal_key", {{"half_unit", 2.0f}, {"unit", 1.0f}},
                      to(&S::cache, &Wc::normal_key_scale)));
    add(flag("world_cache.first_bounce_leak_rule", to(&S::cache, &Wc::first_bounce_leak_rule)));
    add(choice<bool>("world_cache.hit_normal", {{"vertex", true}, {"face_toward_ray", false}},
                     to(&S::gi, &Gi::hit_cache_normal_vertex), to(&S::cache, &Wc::hit_normal_vertex)));
    add(integer("world_cache.update_soft_cap", to(&S::cache, &Wc::update_soft_cap)));
    add(integer("world_cache.workgroup_size", to(&S::cache, &Wc::update_workgroup_size)));
    add(choice<bool>("world_cache.cache_to_cache_life", {{"atomic_max", false}, {"full", true}},
                     to(&S::cache, &Wc::cache_to_cache_full)));
    add(choice<bool>("world_cache.blend", {{"adaptive", true}, {"fixed", false}}, to(&S::cache, &Wc::adaptive_blend)));
    add(number("world_cache.max_samples", to(&S::cache, &Wc::max_samples)));
    add(number("world_cache.adaptive_exponent", to(&S::cache, &Wc::adaptive_exponent)));
    add(number("world_cache.delta_blend", to(&S::cache, &Wc::delta_blend)));
    add(integer("world_cache.di_samples", to(&S::cache, &Wc::di_samples)));
    add(number("world_cache.gi_ray_tmax", to(&S::cache, &Wc::gi_ray_tmax)));
    add(choice<bool>("world_cache.gi_ray_direction", {{"unnormalised", true}, {"normalised", false}},
                     to(&S::cache, &Wc::gi_reach_cosine)));
    add(choice<bool>("world_cache.direct_light_zero_channel", {{"drop", true}, {"keep", false}},
                     to(&S::cache, &Wc::drop_zero_channel_light)));
    add(choice<bool>("world_cache.direct_light_cosine", {{"applied", false}, {"missing", true}},
                     to(&S::cache, &Wc::direct_light_cosine_missing)));
    add(choice<bool>("world_cache.direct_light_candidates", {{"light_tiles", true}, {"own", false}},
                     to(&S::cache, &Wc::tile_candidates)));
    add(choice<bool>("world_cache.light_tiles_frame", {{"current", false}, {"previous", true}},
                     to(&S::cache, &Wc::tiles_previous_frame)));
    return r;
  }();
  return rows;
}

// ---- The table: the radiance-cascades profile (RcSettings) ----

const std::vector<Row<Rc>>& rc_rows() {
  static const std::vector<Row<Rc>> rows = [] {
    std::vector<Row<Rc>> r;
    r.push_back(choice<bool, Rc>("rc.distance_field", {{"analytic", false}, {"jfa", true}}, to(&Rc::jfa)));
    r.push_back(integer_clamped<Rc>("rc.resolution_factor", 0, 8, to(&Rc::resolution_factor)));
    r.push_back(number<Rc>("rc.interval0", to(&Rc::interval0)));
    r.push_back(integer_clamped<Rc>("rc.max_cascades", 1, shader::RC_MAX_CASCADES, to(&Rc::max_cascades)));
    r.push_back(integer_clamped<Rc>("rc.cascade_count", 0, shader::RC_MAX_CASCADES, to(&Rc::cascade_count)));
    r.push_back(integer_clamped<Rc>("rc.max_raymarch_steps", 1, 4096, to(&Rc::max_steps)));
    r.push_back(number<Rc>("rc.hit_epsilon", to(&Rc::hit_epsilon)));
    r.push_back(choice<std::uint32_t, Rc>("rc.mipmap_divisor",
                                          {{"probe_width_x2", shader::RC_MIPMAP_PROBE_WIDTH_X2},
                                           {"ray_count", shader::RC_MIPMAP_RAY_COUNT}},
                                          to(&Rc::mipmap_mode)));
    r.push_back(choice<std::uint32_t, Rc>("rc.merge",
                                          {{"lesson", shader::RC_MERGE_LESSON},
                                           {"bilinear_fix", shader::RC_MERGE_BILINEAR_FIX}},
                                          to(&Rc::merge)));
    return r;
  }();
  return rows;
}

// ---- Resolving a profile ----

const char* type_name(ProfileKeyType t) {
  switch (t) {
    case ProfileKeyType::integer: return "an integer";
    case ProfileKeyType::number: return "a number";
    case ProfileKeyType::flag: return "a boolean";
    case ProfileKeyType::choice: return "a string";
  }
  return "?";
}

bool has_type(const json& v, ProfileKeyType t) {
  switch (t) {
    case ProfileKeyType::integer: return v.is_number_integer();
    case ProfileKeyType::number: return v.is_number();
    case ProfileKeyType::flag: return v.is_boolean();
    case ProfileKeyType::choice: return v.is_string();
  }
  return false;
}

const char* family_name(ProfileFamily f) {
  return f == ProfileFamily::solari ? "Solari profile (solari-*.json)" : "radiance-cascades profile";
}

template <class Target>
Target resolve(const std::vector<Row<Target>>& rows, const Profile& p) {
  Target t{};
  for (const Row<Target>& row : rows) {
    const std::string& key = row.info.key;
    const std::string path = "/values/" + json_pointer_token(key);
    const auto it = p.values.find(key);
    if (it == p.values.end())
      throw InputError(p.file.string(), path,
                       fmt::format("the key {} ({}), which every {} has", key, type_name(row.info.type),
                                   family_name(row.info.family)));
    if (!has_type(it->second.value, row.info.type))
      throw InputError(p.file.string(), path + "/value",
                       fmt::format("{} for {}, got {}", type_name(row.info.type), key, it->second.value.dump()));
    row.fill(t, it->second.value, p);
  }
  return t;
}

template <class Target>
bool has_all(const std::vector<Row<Target>>& rows, const Profile& p) {
  return std::all_of(rows.begin(), rows.end(), [&](const Row<Target>& r) { return p.values.count(r.info.key) > 0; });
}

}  // namespace

const std::vector<ProfileKeyInfo>& profile_keys() {
  static const std::vector<ProfileKeyInfo> keys = [] {
    std::vector<ProfileKeyInfo> k;
    for (const Row<S>& r : solari_rows()) k.push_back(r.info);
    for (const Row<Rc>& r : rc_rows()) k.push_back(r.info);
    return k;
  }();
  return keys;
}

bool profile_has_family(const Profile& profile, ProfileFamily family) {
  return family == ProfileFamily::solari ? has_all(solari_rows(), profile) : has_all(rc_rows(), profile);
}

RealtimeSettings resolve_solari_profile(const Profile& profile) { return resolve(solari_rows(), profile); }

RcSettings rc_profile_settings(const Profile& profile) { return resolve(rc_rows(), profile); }

RcSettings rc_settings(const Profile& profile, std::uint32_t width, std::uint32_t height) {
  return rc_settings_for_canvas(rc_profile_settings(profile), width, height);
}

const std::string& profile_key_at(std::size_t offset) {
  for (const Row<S>& r : solari_rows())
    if (std::find(r.offsets.begin(), r.offsets.end(), offset) != r.offsets.end()) return r.info.key;
  throw std::logic_error(fmt::format("profile_key_at: no row of gpu/profile_keys.cpp fills the field at {}", offset));
}

std::size_t realtime_settings_offset(const void* field, const RealtimeSettings& within) {
  return offset_in(field, &within);
}

const RealtimeSettings& realtime_settings_probe() { return probe<RealtimeSettings>(); }

}  // namespace gi
