// Citations of Bevy's source in profile texts, and the fingerprint of the
// lines they cite (app/fidelity_command.cpp holds each profile value's
// citations against a Bevy git checkout).
//
// What a profile's `source` writes, and how it is read (tests/bevy_citation_test.cpp):
//   v0.18.0:realtime/restir_di.wgsl:31       a ref (tag, or commit with an
//                                            optional ^), a path, lines
//   f755ea4a71^:realtime/restir.wgsl:259     a commit's parent
//   world_cache_update.wgsl:40               a path alone: the last ref named
//                                            before it in the same text
//   :165-171, :52                            lines alone: the last path too
//   bevy_pbr v0.18.0 render/utils.wgsl:98    a ref named in the prose before
//                                            the path also counts (a tag, a
//                                            commit of 7-40 hex digits with a
//                                            letter and a digit, main@<hex>)
// Lines are `N`, `N-M` or lists of both (`108,122`, `322-333, 519-525`).
// A path is relative to crates/bevy_solari/src/ unless it starts with
// crates/; `render/…` and `bevy_pbr/…` are bevy_pbr's; a bare file name takes
// the folder of the last path before it. Where that guess can be wrong, the
// checkout decides: `candidates` lists the paths to try, in order.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gi {

struct LineRange {
  int first = 0, last = 0;  // 1-based, inclusive
};

struct BevyCitation {
  std::string ref;                      // "v0.18.0", "f755ea4a71^", "4805ca7"
  std::string written_path;             // as the text writes it
  std::vector<std::string> candidates;  // repository paths to try, best first
  std::vector<LineRange> lines;
  std::size_t offset = 0;               // where the citation starts in the text
};

// Every citation of `text`, in order. A citation with no ref named before it
// gets `default_ref` (empty: such a citation has an empty ref).
std::vector<BevyCitation> parse_bevy_citations(std::string_view text, std::string_view default_ref = {});

// "31", "165-171", "108,122".
std::string format_lines(const std::vector<LineRange>& lines);

// "<ref>:<path>:<lines>", the key a profile records the fingerprint under.
std::string citation_key(const std::string& ref, const std::string& path, const std::vector<LineRange>& lines);

// The cited lines of a file's text, each without its leading and trailing
// white space, or false when a line lies beyond the file's end.
bool cited_lines(std::string_view file_text, const std::vector<LineRange>& lines, std::vector<std::string>& out);

// 16 hex digits: XXH3-64 of the lines joined by '\n' (indentation is not
// part of what a line says).
std::string lines_fingerprint(const std::vector<std::string>& lines);

}  // namespace gi
