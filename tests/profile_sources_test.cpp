// Profile sources: every value of every profile in
// scenarios/profiles/ says where Bevy has it. A source begins with a citation
// of Bevy's code at a release tag, `v0.18.0:realtime/restir_di.wgsl:31`
// (path relative to crates/bevy_solari/src/, or from the repository root for
// other crates; a line or a range `:165-171`), or, where a blog post is the
// only source, `post:seeds/<file>:<line>` and the words "blog post only".
// A release profile (solari-0.17, -0.18, -0.19) cites its own tag only,
// everywhere in each source: every constant and switch can be cited at every
// tag (a key with no counterpart in a release, e.g. specular GI in 0.17,
// cites the code that shows its absence), so an older tag in a newer profile
// would mean a value copied without being checked. All profiles hold the same
// keys. FIDELITY.md (same folder) tabulates the values against Bevy's.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "core/profile.h"

namespace gi {
namespace {

const std::regex& leading_citation() {
  static const std::regex re(
      R"(^(v0\.1[789]\.0:[A-Za-z0-9_./-]+\.(wgsl|wesl|rs):[0-9]+(-[0-9]+)?|post:seeds/[A-Za-z0-9_.-]+:[0-9]+))");
  return re;
}

// Every code citation anywhere in a source: tag, path, first and last line.
struct Citation {
  std::string tag, path;
  long first = 0, last = 0;
};

std::vector<Citation> code_citations(const std::string& source) {
  static const std::regex re(R"((v0\.[0-9]+\.[0-9]+):([A-Za-z0-9_./-]+\.(wgsl|wesl|rs)):([0-9]+)(-([0-9]+))?)");
  std::vector<Citation> out;
  for (auto it = std::sregex_iterator(source.begin(), source.end(), re); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    Citation c{m[1].str(), m[2].str(), std::stol(m[4].str()), 0};
    c.last = m[6].matched ? std::stol(m[6].str()) : c.first;
    out.push_back(c);
  }
  return out;
}

// What is wrong with a source (empty when nothing is). `release_tag` is
// "v0.18.0" for solari-0.18 and empty for a profile that is not a release's.
std::string source_problem(const std::string& source, const std::string& release_tag) {
  std::smatch m;
  if (!std::regex_search(source, m, leading_citation()))
    return "does not begin with vX.Y.0:<path>:<line> or post:seeds/<file>:<line>";
  if (source.rfind("post:", 0) == 0 && source.find("blog post only") == std::string::npos)
    return "cites a blog post without saying \"blog post only\"";
  for (const Citation& c : code_citations(source)) {
    if (c.first < 1 || c.last < c.first) return "line range " + std::to_string(c.first) + "-" + std::to_string(c.last);
    if (c.path.rfind("crates/bevy_solari/", 0) == 0)
      return "bevy_solari path " + c.path + " must be relative to crates/bevy_solari/src/";
    if (!release_tag.empty() && c.tag != release_tag)
      return "cites " + c.tag + " in the " + release_tag + " profile (" + c.tag + ":" + c.path + ")";
  }
  return "";
}

// "solari-0.18" -> "v0.18.0"; empty for any other name.
std::string release_tag(const std::string& profile_name) {
  static const std::regex re(R"(^solari-0\.([0-9]+)$)");
  std::smatch m;
  return std::regex_match(profile_name, m, re) ? "v0." + m[1].str() + ".0" : "";
}

std::vector<Profile> all_profiles() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(profile_dir()))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<Profile> out;
  for (const auto& f : files) out.push_back(load_profile(f.string()));
  return out;
}

TEST(ProfileSources, TheCheckRejectsWhatIsNotACitation) {
  EXPECT_EQ(source_problem("v0.18.0:realtime/restir_di.wgsl:31 - INITIAL_SAMPLES = 8", "v0.18.0"), "");
  EXPECT_EQ(source_problem("v0.18.0:realtime/restir_di.wgsl:165-171 - fallback", "v0.18.0"), "");
  EXPECT_EQ(source_problem("v0.18.0:crates/bevy_pbr/src/meshlet/visibility_buffer_resolve.wgsl:107 - ids", "v0.18.0"),
            "");
  EXPECT_EQ(source_problem("post:seeds/solari-0.18.md:12 - blog post only", ""), "");
  EXPECT_NE(source_problem("Bevy 0.18 Solari (seeds/solari-0.18.md): 32", "v0.18.0"), "");
  EXPECT_NE(source_problem("v0.18.0:realtime/restir_di.wgsl - no line", "v0.18.0"), "");
  EXPECT_NE(source_problem("see v0.18.0:realtime/restir_di.wgsl:31", "v0.18.0"), "");
  EXPECT_NE(source_problem("v0.16.0:realtime/restir_di.wgsl:31", ""), "");
  EXPECT_NE(source_problem("v0.18.0:realtime/restir_di.wgsl:31-20", "v0.18.0"), "");
  EXPECT_NE(source_problem("v0.18.0:crates/bevy_solari/src/realtime/restir_di.wgsl:31", "v0.18.0"), "");
  EXPECT_NE(source_problem("post:seeds/solari-0.18.md:12 - the post says so", ""), "");
  // The tag rule reaches citations after the first one.
  EXPECT_NE(source_problem("v0.18.0:realtime/restir_di.wgsl:31 (0.17: v0.17.0:realtime/restir_di.wgsl:30)", "v0.18.0"),
            "");
  EXPECT_EQ(release_tag("solari-0.19"), "v0.19.0");
  EXPECT_EQ(release_tag("my-experiment"), "");
}

TEST(ProfileSources, EveryValueBeginsWithACitationOfItsReleaseTag) {
  const std::vector<Profile> profiles = all_profiles();
  std::set<std::string> names;
  for (const Profile& p : profiles) {
    names.insert(p.name);
    EXPECT_EQ(p.file.stem().string(), p.name) << p.file;
    const std::string tag = release_tag(p.name);
    for (const auto& [key, v] : p.values)
      EXPECT_EQ(source_problem(v.source, tag), "") << p.file.filename().string() << " " << key << ": " << v.source;
  }
  for (const char* release : {"solari-0.17", "solari-0.18", "solari-0.19"}) EXPECT_TRUE(names.count(release)) << release;
}

TEST(ProfileSources, AllProfilesHoldTheSameKeys) {
  const Profile reference = load_profile("solari-0.18");
  std::set<std::string> expected;
  for (const auto& [key, _] : reference.values) expected.insert(key);
  for (const Profile& p : all_profiles()) {
    // The radiance-cascades pipeline's profile has keys of its own (rc.*), and only those.
    if (p.name == "radiance-cascades-lesson") {
      for (const auto& [key, _] : p.values) EXPECT_EQ(key.rfind("rc.", 0), 0u) << key;
      continue;
    }
    std::set<std::string> keys;
    for (const auto& [key, _] : p.values) keys.insert(key);
    for (const std::string& k : expected) EXPECT_TRUE(keys.count(k)) << p.name << " lacks " << k;
    for (const std::string& k : keys) EXPECT_TRUE(expected.count(k)) << p.name << " has " << k << ", solari-0.18 not";
  }
}

// solari-0.19 holds 0.19's own constants where they differ from 0.18's
// (FIDELITY.md); its other values are 0.18's.
TEST(ProfileSources, Solari019HoldsTheConstantsThatChangedIn019) {
  const Profile p19 = load_profile("solari-0.19");
  const std::map<std::string, nlohmann::json> changed = {
      {"restir_di.initial_samples", 8},  // v0.19.0:realtime/restir_di.wgsl:19
      {"restir_di.dissimilar_normal_min_dot", 0.0},  // v0.19.0:realtime/gbuffer_utils.wgsl:45
      {"world_cache.lifetime", 10},  // v0.19.0:realtime/world_cache_query.wgsl:30
      {"world_cache.cell_size_base", 0.15},  // v0.19.0:realtime/world_cache_query.wgsl:35
      {"world_cache.lod_scale", 15.0}};  // v0.19.0:realtime/world_cache_query.wgsl:37
  for (const auto& [key, v] : changed) {
    ASSERT_TRUE(p19.values.count(key)) << key;
    EXPECT_EQ(p19.values.at(key).value, v) << key;
  }
}

}  // namespace
}  // namespace gi
