// How profile texts cite Bevy (core/bevy_citation.h), and the profile files'
// own layout, which `giharness fidelity --record` writes back unchanged.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/bevy_citation.h"
#include "core/profile.h"

namespace gi {
namespace {

std::string summary(const BevyCitation& c) { return c.ref + ":" + c.candidates.front() + ":" + format_lines(c.lines); }

TEST(BevyCitation, ReadsEachFormAProfileWrites) {
  const auto c = parse_bevy_citations(
      "v0.18.0:realtime/restir_di.wgsl:165-171 - the fallback (:182), shaded in gbuffer_utils.wgsl:49-56; "
      "bevy_pbr v0.18.0 render/utils.wgsl:98-106, 110 and f755ea4a71^:realtime/restir.wgsl:259, "
      "Bevy main (4805ca7) realtime/restir.wesl:252-263 (:261), v0.18.0:crates/bevy_pbr/src/x.wgsl:3,7");
  ASSERT_EQ(c.size(), 8u);
  EXPECT_EQ(summary(c[0]), "v0.18.0:crates/bevy_solari/src/realtime/restir_di.wgsl:165-171");
  EXPECT_EQ(summary(c[1]), "v0.18.0:crates/bevy_solari/src/realtime/restir_di.wgsl:182");
  // A bare file name: the last path's folder first, then Solari's folders.
  EXPECT_EQ(summary(c[2]), "v0.18.0:crates/bevy_solari/src/realtime/gbuffer_utils.wgsl:49-56");
  EXPECT_EQ(c[2].candidates.at(1), "crates/bevy_solari/src/scene/gbuffer_utils.wgsl");
  // A ref named in the prose; render/ is bevy_pbr's; a rising list.
  EXPECT_EQ(summary(c[3]), "v0.18.0:crates/bevy_pbr/src/render/utils.wgsl:98-106,110");
  EXPECT_EQ(summary(c[4]), "f755ea4a71^:crates/bevy_solari/src/realtime/restir.wgsl:259");
  EXPECT_EQ(summary(c[5]), "4805ca7:crates/bevy_solari/src/realtime/restir.wesl:252-263");
  EXPECT_EQ(summary(c[6]), "4805ca7:crates/bevy_solari/src/realtime/restir.wesl:261");
  EXPECT_EQ(summary(c[7]), "v0.18.0:crates/bevy_pbr/src/x.wgsl:3,7");
}

TEST(BevyCitation, ProseIsNotACitation) {
  // A number after the lines' comma that does not rise, a unit after a
  // number, a ratio, a word of hex letters, a path with no line.
  const auto c = parse_bevy_citations(
      "v0.17.0:realtime/restir_di.wgsl:30 32u, :31, 8 samples; 1:2 (added), see restir_gi.wgsl and :3x");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(format_lines(c[0].lines), "30");
  EXPECT_EQ(format_lines(c[1].lines), "31");
  // Without a ref before it, a citation takes the default.
  const auto d = parse_bevy_citations("realtime/node.rs:223", "v0.19.0");
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(summary(d[0]), "v0.19.0:crates/bevy_solari/src/realtime/node.rs:223");
  // A full stop after a path that has no line is the sentence's.
  EXPECT_TRUE(parse_bevy_citations("in lib.rs. Then").empty());
}

TEST(BevyCitation, TheFingerprintIgnoresIndentationAndNothingElse) {
  const std::string file = "fn a() {\n    let x = 8u;\n\tlet y = 2u;  \n}\n";
  std::vector<std::string> lines, again;
  ASSERT_TRUE(cited_lines(file, {{2, 3}}, lines));
  EXPECT_EQ(lines, (std::vector<std::string>{"let x = 8u;", "let y = 2u;"}));
  ASSERT_TRUE(cited_lines("let x = 8u;\nlet y = 2u;", {{1, 2}}, again));
  EXPECT_EQ(lines_fingerprint(lines), lines_fingerprint(again));
  ASSERT_TRUE(cited_lines("let x = 9u;\nlet y = 2u;", {{1, 2}}, again));
  EXPECT_NE(lines_fingerprint(lines), lines_fingerprint(again));
  EXPECT_EQ(lines_fingerprint(lines).size(), 16u);
  EXPECT_FALSE(cited_lines(file, {{4, 6}}, again));  // beyond the end
  EXPECT_FALSE(cited_lines(file, {{3, 2}}, again));
}

// --record rewrites a profile through profile_file_text; each profile file is
// already in that layout, so a record changes only its fingerprints.
TEST(BevyCitation, EachProfileFileIsInTheLayoutRecordWrites) {
  for (const auto& e : std::filesystem::directory_iterator(profile_dir())) {
    if (e.path().extension() != ".json") continue;
    std::ifstream in(e.path());
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(profile_file_text(nlohmann::ordered_json::parse(text.str())), text.str()) << e.path();
  }
}

}  // namespace
}  // namespace gi
