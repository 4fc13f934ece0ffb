// `giharness fidelity BEVY_CHECKOUT [--ref REF] [--record]`: every Bevy
// citation of every profile value (core/bevy_citation.h), read at its own ref
// from a Bevy git checkout and held to the fingerprint the profile recorded
// for it ("cited"); with --ref, what upstream did to the cited lines since the
// profile's release (its "bevy_ref").
//
// A citation is `ok` when its lines read as recorded. Drift, exit 1:
//   unrecorded  the profile holds no fingerprint for it (a new or edited
//               citation: read the lines, then --record)
//   changed     the lines read otherwise than recorded (a ref that moved, or
//               another repository); `moved` when the recorded text is still
//               in the file, at other lines
//   missing     the ref, the file or the lines do not exist
//   stale       a fingerprint no citation of the source names any more
// --record writes the fingerprints of unrecorded citations and drops stale
// ones; it never overwrites a changed one (that is for a person to read).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/bevy_citation.h"
#include "core/errors.h"
#include "core/profile.h"
#include "app/commands.h"
#include "app/git_reader.h"

namespace gi {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

struct CitationResult {
  std::string key;     // "<ref>:<path>:<lines>", or the text as written when unresolved
  std::string status;  // ok, unrecorded, changed, moved, missing, stale
  std::string detail;
  std::string ref, path;
  std::vector<LineRange> lines;
  std::vector<std::string> text;  // the cited lines at the ref
  std::string fingerprint;
};

// The first run of `count` lines of `file_text` (trimmed, as cited_lines
// gives them) that `matches` accepts.
template <class Match>
std::optional<LineRange> find_run(const std::string& file_text, std::size_t count, Match matches) {
  const int n = static_cast<int>(std::count(file_text.begin(), file_text.end(), '\n')) + 1;
  const int len = static_cast<int>(count);
  std::vector<std::string> window;
  for (int first = 1; len > 0 && first + len - 1 <= n; ++first) {
    if (!cited_lines(file_text, {{first, first + len - 1}}, window)) break;
    if (matches(window)) return LineRange{first, first + len - 1};
  }
  return std::nullopt;
}

// Where `wanted` stands in `file_text`, as one range.
std::optional<LineRange> find_lines(const std::string& file_text, const std::vector<std::string>& wanted) {
  return find_run(file_text, wanted.size(), [&](const std::vector<std::string>& w) { return w == wanted; });
}

// The first run of `count` lines of `file_text` whose fingerprint is `fingerprint`.
std::optional<LineRange> find_fingerprint(const std::string& file_text, const std::string& fingerprint,
                                          std::size_t count) {
  return find_run(file_text, count, [&](const std::vector<std::string>& w) { return lines_fingerprint(w) == fingerprint; });
}

// Each range of `lines` looked up in `file_text` by its text alone: the
// ranges where they now stand, or nullopt when one is not found.
std::optional<std::vector<LineRange>> relocate(const std::string& file_text, const std::string& old_text,
                                               const std::vector<LineRange>& lines) {
  std::vector<LineRange> found;
  for (const LineRange& r : lines) {
    std::vector<std::string> wanted;
    if (!cited_lines(old_text, {r}, wanted)) return std::nullopt;
    const auto at = find_lines(file_text, wanted);
    if (!at) return std::nullopt;
    found.push_back(*at);
  }
  return found;
}

// The citation's path at its ref: the first candidate the ref holds.
std::optional<std::string> resolve_path(GitReader& git, const BevyCitation& c) {
  for (const std::string& p : c.candidates)
    if (git.file_at(c.ref, p)) return p;
  return std::nullopt;
}

std::vector<CitationResult> check_value(GitReader& git, const Profile& profile, const ProfileValue& value) {
  std::vector<CitationResult> out;
  std::set<std::string> seen;
  for (const BevyCitation& c : parse_bevy_citations(value.source, profile.bevy_ref)) {
    CitationResult r;
    r.ref = c.ref;
    r.lines = c.lines;
    const std::string written = c.ref + ":" + c.written_path + ":" + format_lines(c.lines);
    if (!git.resolve(c.ref)) {
      r.key = written;
      r.status = "missing";
      r.detail = "the checkout has no ref " + c.ref;
    } else if (const auto path = resolve_path(git, c); !path) {
      r.key = written;
      r.status = "missing";
      r.detail = fmt::format("no file {} at {} (tried {})", c.written_path, c.ref, fmt::join(c.candidates, ", "));
    } else {
      r.path = *path;
      r.key = citation_key(c.ref, r.path, c.lines);
      const std::string& file = *git.file_at(c.ref, r.path);
      if (!cited_lines(file, c.lines, r.text)) {
        r.status = "missing";
        r.detail = fmt::format("lines {} lie beyond the end of {} at {}", format_lines(c.lines), r.path, c.ref);
      } else {
        r.fingerprint = lines_fingerprint(r.text);
        const auto recorded = value.cited.find(r.key);
        if (recorded == value.cited.end()) {
          r.status = "unrecorded";
        } else if (recorded->second == r.fingerprint) {
          r.status = "ok";
        } else if (const auto at = find_fingerprint(file, recorded->second, r.text.size())) {
          r.status = "moved";
          r.detail = fmt::format("the recorded text stands at lines {}", format_lines({*at}));
        } else {
          r.status = "changed";
          r.detail = "recorded " + recorded->second + ", the lines now read " + r.fingerprint;
        }
      }
    }
    if (!seen.insert(r.key).second) continue;  // the same lines cited twice in one source
    out.push_back(std::move(r));
  }
  for (const auto& [key, fingerprint] : value.cited)
    if (!seen.count(key)) {
      CitationResult r;
      r.key = key;
      r.status = "stale";
      r.detail = "recorded " + fingerprint + ", but the source cites it no more";
      out.push_back(std::move(r));
    }
  return out;
}

// What upstream did to one citation of the profile's own ref: same (the
// lines read the same at `to`), moved (the text stands at other lines),
// changed, or gone (the file is not there; a .wgsl is also looked for as
// .wesl, Bevy's shader language since the WESL migration).
json upstream_of(GitReader& git, const CitationResult& r, const std::string& to) {
  json u = {{"citation", r.key}};
  std::string path = r.path;
  const std::optional<std::string>* file = &git.file_at(to, path);
  if (!*file && path.size() > 5 && path.substr(path.size() - 5) == ".wgsl") {
    const std::string wesl = path.substr(0, path.size() - 5) + ".wesl";
    if (git.file_at(to, wesl)) {
      path = wesl;
      file = &git.file_at(to, path);
    }
  }
  if (!*file) {
    u["status"] = "gone";
    return u;
  }
  u["path"] = path;
  std::vector<std::string> now;
  if (path == r.path && cited_lines(**file, r.lines, now) && now == r.text) {
    u["status"] = "same";
    return u;
  }
  const auto moved = relocate(**file, *git.file_at(r.ref, r.path), r.lines);
  u["status"] = moved ? "moved" : "changed";
  if (moved) u["lines"] = format_lines(*moved);
  return u;
}

std::vector<std::filesystem::path> profiles_to_check(const FidelityOptions& options) {
  std::vector<std::filesystem::path> files;
  if (!options.profiles.empty()) {
    for (const std::string& p : options.profiles) files.push_back(load_profile(p).file);
    return files;
  }
  for (const auto& e : std::filesystem::directory_iterator(profile_dir()))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

void record(const Profile& profile, const std::map<std::string, std::vector<CitationResult>>& results) {
  // The file again, in its own key order (load_profile has validated it).
  std::ifstream in(profile.file);
  ordered_json doc = ordered_json::parse(in);
  for (auto& [key, value] : doc["values"].items()) {
    const auto it = results.find(key);
    if (it == results.end()) continue;
    ordered_json cited = ordered_json::object();
    const auto& recorded = profile.values.at(key).cited;
    for (const CitationResult& r : it->second) {
      if (r.status == "stale") continue;
      if (const auto old = recorded.find(r.key); old != recorded.end()) {
        cited[r.key] = old->second;  // ok, or drift that a person reads before it is recorded again
      } else if (r.status == "unrecorded") {
        cited[r.key] = r.fingerprint;
      }
    }
    if (cited.empty()) {
      value.erase("cited");
    } else {
      value["cited"] = cited;
    }
  }
  write_text_file(profile.file, profile_file_text(doc));
}

}  // namespace

int run_fidelity_command(const FidelityOptions& options) {
  GitReader git(options.checkout);
  std::optional<std::string> upstream;
  if (!options.upstream_ref.empty()) {
    upstream = git.resolve(options.upstream_ref);
    if (!upstream) throw InputError("--ref", "", "a ref of " + options.checkout.string() + ", got " + options.upstream_ref);
  }
  json report = {{"checkout", options.checkout.string()}, {"profiles", json::array()}};
  if (upstream) report["upstream"] = {{"ref", options.upstream_ref}, {"commit", *upstream}};
  std::size_t drift = 0;
  for (const std::filesystem::path& file : profiles_to_check(options)) {
    const Profile profile = load_profile(file.string());
    if (profile.bevy_ref.empty()) {
      fmt::print("{}: models no Bevy release (no bevy_ref), not checked\n", profile.name);
      continue;
    }
    std::map<std::string, std::vector<CitationResult>> results;
    std::map<std::string, std::size_t> counts;
    for (const auto& [key, value] : profile.values) {
      results[key] = check_value(git, profile, value);
      for (const CitationResult& r : results[key]) ++counts[r.status];
    }
    json p = {{"name", profile.name}, {"file", profile.file.string()}, {"bevy_ref", profile.bevy_ref},
              {"values", json::object()}};
    std::size_t total = 0, profile_drift = 0;
    for (const auto& [key, list] : results) {
      json v = json::array();
      for (const CitationResult& r : list) {
        ++total;
        json c = {{"citation", r.key}, {"status", r.status}};
        if (!r.detail.empty()) c["detail"] = r.detail;
        if (!r.fingerprint.empty()) c["fingerprint"] = r.fingerprint;
        v.push_back(c);
        const bool drifted = r.status != "ok" && !(options.record && (r.status == "unrecorded" || r.status == "stale"));
        if (!drifted) continue;
        ++profile_drift;
        fmt::print("  {} {}: {}{}\n", r.status, key, r.key, r.detail.empty() ? "" : " (" + r.detail + ")");
        if (!r.text.empty() && r.status != "unrecorded") fmt::print("      {}\n", r.text.front());
      }
      p["values"][key] = v;
    }
    std::string tally;
    for (const auto& [status, n] : counts) tally += fmt::format("{}{} {}", tally.empty() ? "" : ", ", n, status);
    fmt::print("{} ({}): {} citations in {} values: {}{}\n", profile.name, profile.bevy_ref, total,
               profile.values.size(), tally.empty() ? "none" : tally,
               options.record ? "; fingerprints recorded" : "");
    p["counts"] = counts;
    p["drifted"] = profile_drift;
    drift += profile_drift;
    if (options.record) record(profile, results);

    if (upstream) {
      std::set<std::string> files;
      std::map<std::string, std::vector<std::string>> keys_by_file;
      json changed_keys = json::object();
      std::map<std::string, std::size_t> up_counts;
      for (const auto& [key, list] : results)
        for (const CitationResult& r : list) {
          if (r.ref != profile.bevy_ref || r.path.empty() || r.text.empty()) continue;
          files.insert(r.path);
          keys_by_file[r.path].push_back(key);
          json u = upstream_of(git, r, *upstream);
          ++up_counts[u["status"].get<std::string>()];
          if (u["status"] != "same") changed_keys[key].push_back(u);
        }
      const std::vector<GitCommit> commits =
          git.commits_between(profile.bevy_ref, *upstream, std::vector<std::string>(files.begin(), files.end()));
      json jc = json::array();
      fmt::print("  since {}, {} commits on {} touch the {} files it cites:\n", profile.bevy_ref, commits.size(),
                 options.upstream_ref, files.size());
      for (const GitCommit& c : commits) {
        std::set<std::string> keys;
        for (const std::string& f : c.files)
          if (keys_by_file.count(f)) keys.insert(keys_by_file[f].begin(), keys_by_file[f].end());
        fmt::print("    {} {} {} ({} files, {} keys cite them)\n", c.hash, c.date, c.subject, c.files.size(),
                   keys.size());
        jc.push_back({{"commit", c.hash}, {"date", c.date}, {"subject", c.subject}, {"files", c.files},
                      {"keys", std::vector<std::string>(keys.begin(), keys.end())}});
      }
      std::string up_tally;
      for (const auto& [status, n] : up_counts)
        up_tally += fmt::format("{}{} {}", up_tally.empty() ? "" : ", ", n, status);
      fmt::print("  its {} citations at {}: {}; {} keys cite lines that moved, changed or went:\n",
                 profile.bevy_ref, options.upstream_ref, up_tally, changed_keys.size());
      for (const auto& [key, list] : changed_keys.items()) {
        std::size_t moved = 0, other = 0;
        for (const json& u : list) ++(u["status"] == "moved" ? moved : other);
        fmt::print("    {}: {} moved, {} changed or gone\n", key, moved, other);
      }
      p["upstream"] = {{"commits", jc}, {"counts", up_counts}, {"keys", changed_keys}};
    }
    report["profiles"].push_back(p);
  }
  report["drifted"] = drift;
  if (!options.out.empty()) write_json_file(options.out, report);
  fmt::print("{} drifted citation{}\n", drift, drift == 1 ? "" : "s");
  return drift == 0 ? 0 : 1;
}

}  // namespace gi
