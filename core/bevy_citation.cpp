#include "core/bevy_citation.h"

#include <algorithm>
#include <cctype>
#include <optional>

#include <fmt/format.h>
#include <xxhash.h>

namespace gi {
namespace {

bool is_path_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' || c == '-';
}
bool is_word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
bool is_hex(char c) { return std::isdigit(static_cast<unsigned char>(c)) || (c >= 'a' && c <= 'f'); }
bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }

bool ends_with(std::string_view s, std::string_view tail) {
  return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}
bool starts_with(std::string_view s, std::string_view head) { return s.substr(0, head.size()) == head; }

struct Scanned {
  std::string text;
  std::size_t end = 0;
};

// A ref at `i`: v<d>.<d>.<d>, main@<hex>, or 7-40 hex digits (a letter and a
// digit among them) with an optional '^'; nothing of a word may follow.
std::optional<Scanned> scan_ref(std::string_view t, std::size_t i) {
  if (i > 0 && is_word_char(t[i - 1])) return std::nullopt;
  std::size_t j = i;
  if (j < t.size() && t[j] == 'v') {
    ++j;
    int parts = 0;
    while (parts < 3) {
      const std::size_t start = j;
      while (j < t.size() && is_digit(t[j])) ++j;
      if (j == start) return std::nullopt;
      if (++parts < 3) {
        if (j >= t.size() || t[j] != '.') return std::nullopt;
        ++j;
      }
    }
    if (j < t.size() && is_word_char(t[j])) return std::nullopt;
    return Scanned{std::string(t.substr(i, j - i)), j};
  }
  const bool main_at = starts_with(t.substr(i), "main@");
  if (main_at) j += 5;
  const std::size_t hex_start = j;
  bool letter = false, digit = false;
  while (j < t.size() && is_hex(t[j])) {
    (is_digit(t[j]) ? digit : letter) = true;
    ++j;
  }
  const std::size_t n = j - hex_start;
  if (n < 7 || n > 40 || !letter || !digit) return std::nullopt;
  if (j < t.size() && t[j] == '^') ++j;
  if (j < t.size() && is_word_char(t[j])) return std::nullopt;
  return Scanned{std::string(t.substr(hex_start, j - hex_start)), j};
}

// A path at `i` ending in .wgsl, .wesl or .rs, not inside a longer path.
std::optional<Scanned> scan_path(std::string_view t, std::size_t i) {
  if (i > 0 && is_path_char(t[i - 1])) return std::nullopt;
  std::size_t j = i;
  while (j < t.size() && is_path_char(t[j])) ++j;
  std::string_view p = t.substr(i, j - i);
  // A sentence's full stop is not part of the path.
  while (!p.empty() && p.back() == '.') p.remove_suffix(1);
  if (!(ends_with(p, ".wgsl") || ends_with(p, ".wesl") || ends_with(p, ".rs"))) return std::nullopt;
  if (p.front() == '.' || p.front() == '/' || p.front() == '-') return std::nullopt;
  return Scanned{std::string(p), i + p.size()};
}

int read_number(std::string_view t, std::size_t& j) {
  long v = 0;
  const std::size_t start = j;
  while (j < t.size() && is_digit(t[j]) && j - start < 7) v = v * 10 + (t[j++] - '0');
  return static_cast<int>(v);
}

// Lines at `i` (just after the ':'): N, N-M, and increasing list items.
std::optional<std::pair<std::vector<LineRange>, std::size_t>> scan_lines(std::string_view t, std::size_t i) {
  std::vector<LineRange> out;
  std::size_t j = i;
  auto range_at = [&](std::size_t& k) -> std::optional<LineRange> {
    if (k >= t.size() || !is_digit(t[k])) return std::nullopt;
    LineRange r;
    r.first = r.last = read_number(t, k);
    if (k + 1 < t.size() && t[k] == '-' && is_digit(t[k + 1])) {
      ++k;
      r.last = read_number(t, k);
    }
    if (k < t.size() && is_word_char(t[k])) return std::nullopt;  // "32u", "3x"
    return r;
  };
  const auto first = range_at(j);
  if (!first) return std::nullopt;
  out.push_back(*first);
  for (;;) {
    std::size_t k = j;
    if (k >= t.size() || t[k] != ',') break;
    ++k;
    if (k < t.size() && t[k] == ' ') ++k;
    const auto next = range_at(k);
    // Prose after a comma ("…:31, 8 samples") is not a line: list items rise.
    if (!next || next->first <= out.back().last) break;
    out.push_back(*next);
    j = k;
  }
  return std::make_pair(std::move(out), j);
}

void add_unique(std::vector<std::string>& v, std::string s) {
  if (std::find(v.begin(), v.end(), s) == v.end()) v.push_back(std::move(s));
}

std::vector<std::string> path_candidates(const std::string& written, const std::string& last_folder) {
  std::vector<std::string> c;
  const std::string solari = "crates/bevy_solari/src/";
  if (starts_with(written, "crates/")) {
    c.push_back(written);
  } else if (starts_with(written, "bevy_") && written.find('/') != std::string::npos) {
    c.push_back("crates/" + written);
  } else if (starts_with(written, "render/")) {
    add_unique(c, "crates/bevy_pbr/src/" + written);
    add_unique(c, solari + written);
  } else if (written.find('/') != std::string::npos) {
    add_unique(c, solari + written);
    add_unique(c, "crates/" + written);
  } else {
    if (!last_folder.empty()) add_unique(c, last_folder + written);
    for (const char* folder : {"realtime/", "scene/", "pathtracer/", ""}) add_unique(c, solari + folder + written);
    add_unique(c, "crates/bevy_pbr/src/render/" + written);
  }
  return c;
}

std::string folder_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace

std::vector<BevyCitation> parse_bevy_citations(std::string_view t, std::string_view default_ref) {
  std::vector<BevyCitation> out;
  std::string ref(default_ref);
  std::string last_folder;
  std::size_t i = 0;
  auto add = [&](BevyCitation c) {
    if (!c.candidates.empty()) last_folder = folder_of(c.candidates.front());
    out.push_back(std::move(c));
  };
  while (i < t.size()) {
    // <ref>:<path>:<lines>
    if (const auto r = scan_ref(t, i)) {
      if (r->end < t.size() && t[r->end] == ':') {
        if (const auto p = scan_path(t, r->end + 1); p && p->end < t.size() && t[p->end] == ':') {
          if (const auto l = scan_lines(t, p->end + 1)) {
            ref = r->text;
            add({ref, p->text, path_candidates(p->text, last_folder), l->first, i});
            i = l->second;
            continue;
          }
        }
      }
      ref = r->text;  // a ref in the prose: what follows cites it
      i = r->end;
      continue;
    }
    // <path>:<lines>
    if (const auto p = scan_path(t, i)) {
      if (p->end < t.size() && t[p->end] == ':') {
        if (const auto l = scan_lines(t, p->end + 1)) {
          add({ref, p->text, path_candidates(p->text, last_folder), l->first, i});
          i = l->second;
          continue;
        }
      }
      i = p->end;
      continue;
    }
    // :<lines> after a space or an opening mark: the last path's lines
    if (t[i] == ':' && !out.empty() && (t[i - 1] == ' ' || t[i - 1] == '(' || t[i - 1] == ',' || t[i - 1] == ';')) {
      if (const auto l = scan_lines(t, i + 1)) {
        const BevyCitation& last = out.back();  // its ref too: a ref in the prose since names no file
        BevyCitation c{last.ref, last.written_path, last.candidates, l->first, i};
        add(std::move(c));
        i = l->second;
        continue;
      }
    }
    ++i;
  }
  return out;
}

std::string format_lines(const std::vector<LineRange>& lines) {
  std::string s;
  for (const LineRange& r : lines) {
    if (!s.empty()) s += ",";
    s += r.first == r.last ? fmt::format("{}", r.first) : fmt::format("{}-{}", r.first, r.last);
  }
  return s;
}

std::string citation_key(const std::string& ref, const std::string& path, const std::vector<LineRange>& lines) {
  return ref + ":" + path + ":" + format_lines(lines);
}

bool cited_lines(std::string_view text, const std::vector<LineRange>& lines, std::vector<std::string>& out) {
  std::vector<std::string_view> all;
  for (std::size_t start = 0; start <= text.size();) {
    std::size_t nl = text.find('\n', start);
    if (nl == std::string_view::npos) {
      if (start < text.size()) all.push_back(text.substr(start));
      break;
    }
    all.push_back(text.substr(start, nl - start));
    start = nl + 1;
  }
  out.clear();
  for (const LineRange& r : lines) {
    if (r.first < 1 || r.last < r.first || static_cast<std::size_t>(r.last) > all.size()) return false;
    for (int n = r.first; n <= r.last; ++n) {
      std::string_view l = all[static_cast<std::size_t>(n - 1)];
      while (!l.empty() && std::isspace(static_cast<unsigned char>(l.front()))) l.remove_prefix(1);
      while (!l.empty() && std::isspace(static_cast<unsigned char>(l.back()))) l.remove_suffix(1);
      out.emplace_back(l);
    }
  }
  return true;
}

std::string lines_fingerprint(const std::vector<std::string>& lines) {
  std::string joined;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    if (k) joined += '\n';
    joined += lines[k];
  }
  return fmt::format("{:016x}", XXH3_64bits(joined.data(), joined.size()));
}

}  // namespace gi
