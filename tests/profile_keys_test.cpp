// The profile table (gpu/profile_keys.h) against the released profiles and
// the sources: the same keys, types and string values in both; no key named
// in C++ outside the table; a --set of any key reaches the settings; the
// settings each released profile resolves to, field by field and define by
// define, as recorded (tests/data/profile_settings/, regenerated with
// GIHARNESS_UPDATE_GOLDEN=1 when a profile's value changes on purpose).
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/profile.h"
#include "core/rc/rc_settings.h"
#include "gpu/profile_keys.h"
#include "gpu/realtime_settings.h"
#include "tests/test_support.h"

namespace gi {
namespace {

using gpu::ShaderDefine;

struct Released {
  const char* name;
  ProfileFamily family;
};
constexpr Released kReleased[] = {{"solari-0.17", ProfileFamily::solari},
                                  {"solari-0.18", ProfileFamily::solari},
                                  {"solari-0.19", ProfileFamily::solari},
                                  {"radiance-cascades-lesson", ProfileFamily::radiance_cascades}};

std::filesystem::path profiles_dir() { return test::source_dir() / "scenarios" / "profiles"; }

Profile released(const char* name) { return load_profile(name, profiles_dir()); }

std::vector<const ProfileKeyInfo*> rows_of(ProfileFamily family) {
  std::vector<const ProfileKeyInfo*> rows;
  for (const ProfileKeyInfo& k : profile_keys())
    if (k.family == family) rows.push_back(&k);
  return rows;
}

// ---- Every field and define, as text ----

std::string g(float v) { return fmt::format("{:.9g}", v); }
std::string g(double v) { return fmt::format("{:.17g}", v); }
std::string g(const std::string& v) { return v; }
template <class T>
std::string g(const T& v) {
  if constexpr (std::is_enum_v<T>) return std::to_string(static_cast<int>(v));
  else if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_same_v<T, glm::vec3>) return fmt::format("{},{},{}", g(v.x), g(v.y), g(v.z));
  else return std::to_string(v);
}
#define F(s, x) out << "  " #x "=" << g(s.x) << "\n"

void defines(std::ostream& out, const std::vector<ShaderDefine>& d) {
  out << "  defines:";
  for (const ShaderDefine& x : d) out << " " << x.name << "=" << x.value;
  out << "\n";
}

std::string describe(const RealtimeSettings& r) {
  std::ostringstream out;
  out << "settings:\n";
  F(r, size_light_tiles_to_scene); F(r, specular_handover_alpha); F(r, normal_map_decode); F(r, motion_vectors);
  F(r, brdf_model); F(r, brdf_model_name); F(r, brdf_fresnel_raw); F(r, brdf_evaluate_clamp); F(r, jacobian_reject);
  F(r, raytracing_mesh_removal_ignored);
  const gpu::DiSettings& d = r.di;
  out << "di:\n";
  F(d, tile_count); F(d, samples_per_tile); F(d, exposure); F(d, log2_radiance); F(d, initial_samples);
  F(d, confidence_cap); F(d, spatial_radius); F(d, spatial_tries); F(d, plane_tolerance); F(d, normal_min_dot);
  F(d, balance_mis); F(d, mis_visibility); F(d, mis_previous_scene); F(d, target_base_color);
  F(d, temporal_permutation); F(d, temporal_fallback); F(d, offscreen_own_pixel); F(d, tile_per_workgroup);
  F(d, visibility_final); F(d, visibility_final_stored); F(d, emissive_unexposed); F(d, sun_center);
  F(d, show_background); F(d, spatial_radius_halving); F(d, background); F(d, initial_visibility_fed_forward);
  F(d, reuse_radiance_scene);
  F(d, chains); F(d, specular_handover_alpha); F(d, shading_base_over_pi); F(d, tile_seed_scrolling);
  defines(out, d.defines());
  const gpu::GiSettings& s = r.gi;
  out << "gi:\n";
  F(s, confidence_cap); F(s, initial_samples); F(s, spatial_radius); F(s, spatial_tries); F(s, plane_tolerance);
  F(s, normal_min_dot); F(s, jacobian_reject); F(s, jacobian_rejection); F(s, jacobian_both);
  F(s, temporal_permutation); F(s, temporal_reuse); F(s, temporal_edge_stats); F(s, path_counters);
  F(s, spatial_radius_halving); F(s, temporal_fallback); F(s, temporal_history_pre_spatial); F(s, target_brdf);
  F(s, empty_no_confidence); F(s, emissive_test); F(s, visibility_final); F(s, visibility_final_stored);
  F(s, cosine_twice); F(s, shading_diffuse); F(s, skip_smooth_metals); F(s, offscreen_own_pixel);
  F(s, consistent_mis); F(s, hit_radiance); F(s, secondary_hits_full); F(s, secondary_albedo_base); F(s, ray_tmax);
  F(s, specular); F(s, specular_reuse_roughness); F(s, specular_power_mis); F(s, specular_path_spread);
  F(s, specular_path_long_ray); F(s, specular_cache_every_vertex); F(s, specular_russian_roulette);
  F(s, specular_vndf_mirror_alpha); F(s, specular_mis_light_pdf_area); F(s, specular_perfect_mirror_metal);
  F(s, specular_sun_nee_only); F(s, specular_mirror_exact); F(s, specular_mesh_tangent_frame);
  F(s, specular_mirror_throughput_brdf);
  F(s, specular_handover_alpha); F(s, specular_max_bounces); F(s, min_perceptual_roughness); F(s, chains);
  defines(out, s.defines());
  const gpu::WorldCacheSettings& c = r.cache;
  out << "cache:\n";
  F(c, cells); F(c, lifetime); F(c, max_probe_steps); F(c, linear_probing); F(c, cell_size_base); F(c, lod_scale);
  F(c, stochastic_lod); F(c, jitter); F(c, jitter_lod_redrawn); F(c, normal_key_scale); F(c, first_bounce_leak_rule);
  F(c, update_soft_cap); F(c, update_workgroup_size); F(c, cache_to_cache_full); F(c, adaptive_blend);
  F(c, max_samples); F(c, adaptive_exponent); F(c, delta_blend); F(c, di_samples); F(c, gi_ray_tmax);
  F(c, gi_reach_cosine); F(c, light_exposure); F(c, log2_radiance); F(c, secondary_hits_full);
  F(c, secondary_albedo_base); F(c, drop_zero_channel_light); F(c, direct_light_cosine_missing); F(c, sun_center);
  F(c, tile_candidates); F(c, tile_count); F(c, tile_samples); F(c, tiles_previous_frame); F(c, glossy_roughness);
  F(c, glossy_bounces); F(c, view); F(c, stats); F(c, root_frame); F(c, external_queries_per_pixel);
  defines(out, c.defines(c.cells));
  return out.str();
}

std::string describe(const RcSettings& s) {
  std::ostringstream out;
  out << "rc:\n";
  F(s, jfa); F(s, resolution_factor); F(s, interval0); F(s, max_cascades); F(s, cascade_count);
  F(s, cascades_for_diagonal); F(s, cascades); F(s, max_steps); F(s, hit_epsilon); F(s, mipmap_mode); F(s, merge);
  out << "  json=" << s.to_json().dump() << "\n";
  return out.str();
}

std::string describe(const Profile& p, ProfileFamily family) {
  return family == ProfileFamily::solari ? describe(realtime_settings(p)) : describe(rc_settings(p, 256, 144));
}

// ---- The table and the released profiles ----

TEST(ProfileKeys, EveryProfileFileIsAReleasedProfileOfAFamily) {
  std::set<std::string> files, listed;
  for (const auto& e : std::filesystem::directory_iterator(profiles_dir()))
    if (e.path().extension() == ".json") files.insert(e.path().stem().string());
  for (const Released& r : kReleased) listed.insert(r.name);
  EXPECT_EQ(files, listed) << "a profile file this test (kReleased) does not hold to the table, or the reverse";
  for (const Released& r : kReleased) EXPECT_TRUE(profile_has_family(released(r.name), r.family)) << r.name;
}

TEST(ProfileKeys, TheTableAndEachReleasedProfileHaveTheSameKeys) {
  std::set<std::string> seen;
  for (const ProfileKeyInfo& k : profile_keys()) EXPECT_TRUE(seen.insert(k.key).second) << "two rows of " << k.key;
  for (const Released& r : kReleased) {
    const Profile p = released(r.name);
    std::set<std::string> table, profile;
    for (const ProfileKeyInfo* k : rows_of(r.family)) table.insert(k->key);
    for (const auto& [key, _] : p.values) profile.insert(key);
    for (const std::string& k : table)
      EXPECT_TRUE(profile.count(k)) << "the table's " << k << " is missing from " << r.name << ".json";
    for (const std::string& k : profile)
      EXPECT_TRUE(table.count(k)) << r.name << ".json has " << k << ", which no row of gpu/profile_keys.cpp reads";
  }
}

TEST(ProfileKeys, TypesAndStringValuesMatchEachReleasedProfile) {
  for (const Released& r : kReleased) {
    const Profile p = released(r.name);
    for (const ProfileKeyInfo* k : rows_of(r.family)) {
      const auto it = p.values.find(k->key);
      if (it == p.values.end()) continue;  // the test above names it
      const nlohmann::json& v = it->second.value;
      const std::string at = std::string(r.name) + " " + k->key;
      switch (k->type) {
        case ProfileKeyType::integer: EXPECT_TRUE(v.is_number_integer()) << at << ": an integer, got " << v; break;
        case ProfileKeyType::number: EXPECT_TRUE(v.is_number()) << at << ": a number, got " << v; break;
        case ProfileKeyType::flag: EXPECT_TRUE(v.is_boolean()) << at << ": a boolean, got " << v; break;
        case ProfileKeyType::choice: {
          EXPECT_TRUE(v.is_string()) << at << ": a string, got " << v;
          const std::set<std::string> table(k->choices.begin(), k->choices.end());
          const std::set<std::string> allowed(it->second.allowed.begin(), it->second.allowed.end());
          EXPECT_EQ(table.size(), k->choices.size()) << at << ": a value listed twice in the table";
          for (const std::string& c : table)
            EXPECT_TRUE(allowed.count(c)) << at << ": the table's value " << c << " is not in the profile's allowed";
          for (const std::string& a : allowed)
            EXPECT_TRUE(table.count(a)) << at << ": the profile allows " << a << ", which the table's row lacks";
          break;
        }
      }
      if (k->type != ProfileKeyType::choice)
        EXPECT_TRUE(it->second.allowed.empty()) << at << ": an \"allowed\" list on a key the table reads as "
                                                << (k->type == ProfileKeyType::flag ? "a boolean" : "a number");
    }
  }
}

// ---- Each key named once in C++ ----

// Quoted strings that begin with a table key's group ("restir_gi." …) in
// `text`: a table key, or a dotted name in a group that is not a file name.
std::vector<std::string> key_mentions(const std::string& text) {
  static const std::regex quoted = [] {
    std::set<std::string> groups;
    for (const ProfileKeyInfo& k : profile_keys()) groups.insert(k.key.substr(0, k.key.find('.')));
    std::string alternatives;
    for (const std::string& g : groups) alternatives += (alternatives.empty() ? "" : "|") + g;
    return std::regex("\"((?:" + alternatives + ")\\.[A-Za-z0-9_.]*)");
  }();
  static const std::regex file_name(R"(.*\.(h|hpp|cpp|glsl|comp|json|wgsl)$)");
  std::vector<std::string> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), quoted); it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1].str();
    if (!std::regex_match(name, file_name)) found.push_back(name);
  }
  return found;
}

TEST(ProfileKeys, TheScanFindsAStrayKeyAndSkipsFileNames) {
  EXPECT_EQ(key_mentions("  s.x = p.number(\"restir_gi.confidence_cap\");\n"),
            std::vector<std::string>{"restir_gi.confidence_cap"});
  EXPECT_EQ(key_mentions("p.text(\"restir_gi.no_such_key\")"), std::vector<std::string>{"restir_gi.no_such_key"});
  EXPECT_TRUE(key_mentions("#include \"light_tiles.h\"  // restir_gi.confidence_cap, unquoted").empty());
}

TEST(ProfileKeys, EachKeyIsNamedOnlyInTheTable) {
  const std::filesystem::path root = test::source_dir();
  const std::string table_file = "gpu/profile_keys.cpp";
  std::map<std::string, int> in_table;
  for (const char* dir : {"core", "gpu", "reports", "checks", "replay", "app"}) {
    for (const auto& e : std::filesystem::recursive_directory_iterator(root / dir)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".h" && ext != ".cpp" && ext != ".hpp" && ext != ".cc")) continue;
      const std::string rel = std::filesystem::relative(e.path(), root).generic_string();
      for (const std::string& name : key_mentions(test::read_text(e.path()))) {
        if (rel == table_file) ++in_table[name];
        else ADD_FAILURE() << rel << " names the profile key \"" << name
                           << "\": read it through the table (gpu/profile_keys.cpp) and its settings field instead";
      }
    }
  }
  for (const ProfileKeyInfo& k : profile_keys()) EXPECT_EQ(in_table[k.key], 1) << k.key << " in " << table_file;
  for (const auto& [name, n] : in_table) {
    const bool row = std::any_of(profile_keys().begin(), profile_keys().end(),
                                 [&](const ProfileKeyInfo& k) { return k.key == name; });
    EXPECT_TRUE(row) << table_file << " names \"" << name << "\" outside a row";
  }
}

// ---- Overrides reach the settings ----

TEST(ProfileKeys, ASetReachesTheSettingsAndTheDefines) {
  Profile p = released("solari-0.18");
  apply_set(p, "restir_gi.confidence_cap=12");
  const RealtimeSettings s = realtime_settings(p);
  EXPECT_EQ(s.gi.confidence_cap, 12.0f);
  const auto d = s.gi.defines();
  const auto cap = std::find_if(d.begin(), d.end(), [](const ShaderDefine& x) { return x.name == "GI_CONFIDENCE_CAP"; });
  ASSERT_NE(cap, d.end());
  EXPECT_EQ(cap->value, "12.0");
  // A key DI and the cache share: one row, both fields.
  apply_set(p, "light_tiles.exposure=0.5");
  const RealtimeSettings e = realtime_settings(p);
  EXPECT_EQ(e.di.exposure, 0.5f);
  EXPECT_EQ(e.cache.light_exposure, 0.5f);
  // A key DI and GI share.
  apply_set(p, "restir_di.spatial_tries=3");
  const RealtimeSettings t = realtime_settings(p);
  EXPECT_EQ(t.di.spatial_tries, 3u);
  EXPECT_EQ(t.gi.spatial_tries, 3u);
}

// Another value of every key (each other string of a choice) changes what
// the profile resolves to: no row fills nothing, none is shadowed by another.
TEST(ProfileKeys, EveryKeysOverrideChangesTheSettings) {
  for (const auto& [name, family] : {std::pair{"solari-0.18", ProfileFamily::solari},
                                     std::pair{"radiance-cascades-lesson", ProfileFamily::radiance_cascades}}) {
    const Profile base = released(name);
    const std::string before = describe(base, family);
    for (const ProfileKeyInfo* k : rows_of(family)) {
      if (!k->recorded_only.empty()) continue;
      const nlohmann::json& v = base.values.at(k->key).value;
      std::vector<std::string> others;
      // An integer profile value of a number key stays an integer (core/profile.h).
      const ProfileKeyType as = v.is_number_integer() ? ProfileKeyType::integer : k->type;
      switch (as) {
        case ProfileKeyType::integer: {
          const long long i = v.get<long long>();
          others.push_back(std::to_string(i > 1 ? i - 1 : i + 1));
          break;
        }
        case ProfileKeyType::number: others.push_back(fmt::format("{:.17g}", v.get<double>() + 0.25)); break;
        case ProfileKeyType::flag: others.push_back(v.get<bool>() ? "false" : "true"); break;
        case ProfileKeyType::choice:
          for (const std::string& c : k->choices)
            if (c != v.get<std::string>()) others.push_back(c);
          break;
      }
      for (const std::string& o : others) {
        Profile p = base;
        apply_set(p, k->key + "=" + o);
        EXPECT_NE(describe(p, family), before) << name << ": --set " << k->key << "=" << o << " changed nothing";
      }
    }
  }
}

// ---- Bad profiles ----

TEST(ProfileKeys, AProfileWithoutAKeyOrOfTheWrongTypeIsBadInputAtTheKey) {
  Profile p = released("solari-0.18");
  p.values.erase("restir_gi.confidence_cap");
  try {
    realtime_settings(p);
    FAIL() << "a profile without restir_gi.confidence_cap resolved";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), p.file.string());
    EXPECT_EQ(e.json_path(), "/values/restir_gi.confidence_cap");
  }
  Profile q = released("solari-0.18");
  q.values.at("specular.enabled").value = 1;  // what a hand-written profile may hold
  try {
    realtime_settings(q);
    FAIL() << "an integer specular.enabled resolved";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/values/specular.enabled/value");
  }
  Profile r = released("solari-0.18");
  r.values.at("restir_gi.hit_radiance").value = "photon_map";  // allowed by its own file, unknown to the table
  try {
    realtime_settings(r);
    FAIL() << "an unknown restir_gi.hit_radiance resolved";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/values/restir_gi.hit_radiance/value");
  }
  EXPECT_THROW(realtime_settings(released("radiance-cascades-lesson")), InputError);
}

TEST(ProfileKeys, ARowsRangeKeepsItsError) {
  Profile p = released("solari-0.18");
  apply_set(p, "restir_gi.initial_samples=65");
  try {
    realtime_settings(p);
    FAIL() << "restir_gi.initial_samples 65 resolved";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "profile solari-0.18");
    EXPECT_EQ(e.json_path(), "restir_gi.initial_samples");
    EXPECT_EQ(e.expected(), "an integer from 1 to 64, got 65");
  }
}

TEST(ProfileKeys, AFieldNamesTheKeyThatFillsIt) {
  EXPECT_EQ(profile_key_of(&RealtimeSettings::cache, &gpu::WorldCacheSettings::cells), "world_cache.cells");
  EXPECT_EQ(profile_key_of(&RealtimeSettings::cache, &gpu::WorldCacheSettings::update_workgroup_size),
            "world_cache.workgroup_size");
  // A shared key's second field names it too.
  EXPECT_EQ(profile_key_of(&RealtimeSettings::gi, &gpu::GiSettings::spatial_tries), "restir_di.spatial_tries");
  EXPECT_THROW(profile_key_of(&RealtimeSettings::cache, &gpu::WorldCacheSettings::view), std::logic_error);
}

// ---- The settings of each released profile, as recorded ----

TEST(ProfileKeys, EachReleasedProfileResolvesToItsRecordedSettings) {
  const std::filesystem::path dir = test::source_dir() / "tests" / "data" / "profile_settings";
  const bool update = std::getenv("GIHARNESS_UPDATE_GOLDEN") != nullptr;
  for (const Released& r : kReleased) {
    const std::string now = describe(released(r.name), r.family);
    const std::filesystem::path file = dir / (std::string(r.name) + ".txt");
    if (update) {
      std::filesystem::create_directories(dir);
      std::ofstream(file) << now;
      continue;
    }
    ASSERT_TRUE(std::filesystem::exists(file)) << file << " (GIHARNESS_UPDATE_GOLDEN=1 writes it)";
    EXPECT_EQ(test::read_text(file), now)
        << r.name << ": its settings or defines moved. On purpose (a profile value, a new key)? "
        << "GIHARNESS_UPDATE_GOLDEN=1 build/tests/giharness_unit_tests --gtest_filter=ProfileKeys.* rewrites "
        << file.string();
  }
}

}  // namespace
}  // namespace gi
