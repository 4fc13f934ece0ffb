// Profiles (docs/design.md §3 "Profiles"): every constant and behavioural switch of
// the pipeline, each with its source, in scenarios/profiles/<name>.json. A
// scenario names one and overrides single values ("overrides"); the command
// line overrides again (`--profile`, `--set key=value`). Every resolved value,
// with where it came from, goes into summary.json.
//
// File format: {"name", "description", "bevy_ref" (optional: the Bevy tag or
// commit the profile models), "values": {"<key>": {"value": v, "source": "…",
// "allowed": [strings, optional], "cited": {citation: fingerprint, optional}}}}.
// "cited" holds, per Bevy citation in the source (core/bevy_citation.h), the
// fingerprint of the lines it cites; `giharness fidelity` records and checks
// them against a Bevy checkout. Keys are dotted (restir_di.mis); a value's
// type (integer, number, boolean, string) is fixed by the profile, and
// overrides must match it (an integer is accepted where a number is
// expected). The code reads no key here: gpu/profile_keys.cpp, the profile
// table, names each key once and turns a profile into settings.
#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

struct Scenario;

struct ProfileValue {
  nlohmann::json value;
  std::string source;                 // where the value comes from (Bevy version, post, our choice)
  std::vector<std::string> allowed;   // strings: the permitted values (empty: any)
  std::string set_by = "profile";     // "profile", "scenario overrides", "--set"
  std::map<std::string, std::string> cited;  // "<ref>:<path>:<lines>" -> fingerprint of those lines
};

struct Profile {
  std::string name;
  std::string bevy_ref;  // empty: the profile models no Bevy release (radiance cascades)
  std::filesystem::path file;
  std::map<std::string, ProfileValue> values;

  // Typed reads, for tests and tools that look at one value (the run's code
  // reads every key through the profile table, gpu/profile_keys.h);
  // std::logic_error for a key the profile lacks or a wrong type.
  long long integer(const std::string& key) const;
  double number(const std::string& key) const;
  bool flag(const std::string& key) const;
  const std::string& text(const std::string& key) const;

  // {"name", "file", "values": {key: {"value", "source", "set_by"}}}
  nlohmann::json to_json() const;
};

// The profiles folder: $GIHARNESS_PROFILE_DIR, else <data_dir()>/scenarios/profiles
// (core/data_dir.h).
std::filesystem::path profile_dir();

// Loads <dir>/<name>.json, or `name` itself when it names an existing .json
// file. InputError (file + JSON path) for a missing file, bad JSON, or a
// malformed entry.
Profile load_profile(const std::string& name_or_file, const std::filesystem::path& dir = profile_dir());

// A profile document as the profile files are written: keys in their order,
// two-space indents, arrays of scalars on one line, non-ASCII escaped.
std::string profile_file_text(const nlohmann::ordered_json& doc);

// Applies {"key": value} overrides; InputError naming `file` and
// `json_path`/<key> for an unknown key, a wrong type or a value not allowed.
void apply_overrides(Profile& profile, const nlohmann::json& overrides, const std::string& file,
                     const std::string& json_path, const std::string& set_by);

// Applies one "key=value" (value parsed as JSON, else taken as a string).
// InputError naming "--set" for a malformed item, unknown key or wrong type.
void apply_set(Profile& profile, const std::string& assignment);

// The scenario's profile (or `profile_override`), its overrides, then `sets`.
Profile resolve_profile(const Scenario& scenario, const std::optional<std::string>& profile_override = std::nullopt,
                        const std::vector<std::string>& sets = {});

}  // namespace gi
