// The profile table (gpu/profile_keys.cpp): one row per profile key, the only
// place in C++ a key is named. A row gives the key, its type (integer,
// number, boolean, or a string of listed values), for a string each value
// with the C++ value it stands for, and the settings fields it fills. No row
// has a default: the value is always the profile's, and a profile that lacks
// a key of its family is bad input.
//
// Two families: the Solari profiles (scenarios/profiles/solari-*.json) fill
// RealtimeSettings (gpu/realtime_settings.h), the radiance-cascades profile
// (radiance-cascades-lesson.json) fills RcSettings (core/rc/rc_settings.h).
// tests/profile_keys_test.cpp holds the table and the released profiles to
// each other: the same keys, types and string values, and no key named in
// C++ outside the table.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/profile.h"
#include "core/rc/rc_settings.h"

namespace gi {

struct RealtimeSettings;

enum class ProfileKeyType { integer, number, flag, choice };
enum class ProfileFamily { solari, radiance_cascades };

// One row as the tests and tools see it.
struct ProfileKeyInfo {
  std::string key;
  ProfileKeyType type{};
  ProfileFamily family{};
  std::vector<std::string> choices;  // choice: every value the row knows (the profiles' "allowed")
  std::string recorded_only;         // non-empty: no setting reads the key (why); summary.json records it
};

// Every row, the Solari family's first, each family in the table's order.
const std::vector<ProfileKeyInfo>& profile_keys();

// Whether `profile` has every key of `family`.
bool profile_has_family(const Profile& profile, ProfileFamily family);

// The Solari rows applied to `profile` (no cross-key rule: see
// gpu/realtime_settings.h realtime_settings). InputError naming the profile's
// file and /values/<key> for a key it lacks, a wrong type, or a string the
// row does not list; a row's own range (restir_gi.initial_samples) likewise,
// as "profile <name>" and the key.
RealtimeSettings resolve_solari_profile(const Profile& profile);

// The radiance-cascades rows (counts clamped to what the passes hold).
RcSettings rc_profile_settings(const Profile& profile);
// ... for a width × height canvas (core/rc/rc_settings.h rc_settings_for_canvas).
RcSettings rc_settings(const Profile& profile, std::uint32_t width, std::uint32_t height);

// The Solari key whose row fills the field at `offset` bytes into a
// RealtimeSettings, for a check elsewhere that names the key in its error
// (gpu/passes/world_cache.cpp); std::logic_error when no row fills it.
const std::string& profile_key_at(std::size_t offset);
std::size_t realtime_settings_offset(const void* field, const RealtimeSettings& within);
const RealtimeSettings& realtime_settings_probe();

// The key that fills `part`.`member` of RealtimeSettings, e.g.
// profile_key_of(&RealtimeSettings::cache, &gpu::WorldCacheSettings::cells).
template <class Part, class T>
const std::string& profile_key_of(Part RealtimeSettings::*part, T Part::*member) {
  const RealtimeSettings& probe = realtime_settings_probe();
  return profile_key_at(realtime_settings_offset(&((probe.*part).*member), probe));
}

}  // namespace gi
