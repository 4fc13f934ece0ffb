#include "core/json_input.h"

#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/json_reader.h"

namespace gi {
namespace {

using json = nlohmann::json;

std::string line_column(std::string_view text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return fmt::format("line {}, column {}", line, column);
}

// Length of the UTF-8 sequence starting at text[i], or 0 if it is not one
// (overlong forms, surrogates and code points past U+10FFFF included).
std::size_t utf8_sequence(std::string_view text, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // range of the second byte
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c == 0xE0) n = 3, lo = 0xA0;
  else if (c == 0xED) n = 3, hi = 0x9F;
  else if (c >= 0xE1 && c <= 0xEF) n = 3;
  else if (c == 0xF0) n = 4, lo = 0x90;
  else if (c >= 0xF1 && c <= 0xF3) n = 4;
  else if (c == 0xF4) n = 4, hi = 0x8F;
  else return 0;
  if (i + n > text.size() || b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  return n;
}

// One open array or object of the byte scan, enough to name where it is.
struct OpenContainer {
  bool array = false;
  std::size_t index = 0;    // arrays: the element being read
  std::string key;          // objects: the last key read
  bool expect_key = false;  // objects: the next string is a key
};

std::string pointer_of(const std::vector<OpenContainer>& open, std::size_t most) {
  std::string path;
  for (std::size_t i = 0; i < open.size() && i < most; ++i)
    path = open[i].array ? JsonReader::at(path, open[i].index) : JsonReader::at(path, open[i].key);
  if (open.size() > most) path += "/…";
  return path;
}

// The byte checks and the depth limit, in one pass that does not recurse.
void scan_bytes(std::string_view text, const std::string& file, const JsonLimits& limits) {
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF")
    throw InputError(file, "", "expected JSON without a byte-order mark (a UTF-8 BOM opens the file)");
  std::vector<OpenContainer> open;
  bool in_string = false, escaped = false;
  std::size_t string_start = 0;
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (c == '\0') throw InputError(file, pointer_of(open, 16), "expected no NUL byte; one at " + line_column(text, i));
    const std::size_t n = utf8_sequence(text, i);
    if (n == 0) throw InputError(file, pointer_of(open, 16), "expected valid UTF-8; an invalid byte at " + line_column(text, i));
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
        if (!open.empty() && !open.back().array && open.back().expect_key) {
          open.back().key = std::string(text.substr(string_start, i - string_start));
          open.back().expect_key = false;
        }
      }
    } else if (c == '"') {
      in_string = true;
      string_start = i + 1;
    } else if (c == '[' || c == '{') {
      if (open.size() >= limits.max_depth)
        throw InputError(file, pointer_of(open, 16),
                         fmt::format("expected arrays and objects nested at most {} deep; deeper at {}", limits.max_depth,
                                     line_column(text, i)));
      open.push_back({c == '[', 0, {}, c == '{'});
    } else if ((c == ']' || c == '}') && !open.empty()) {
      open.pop_back();
    } else if (c == ',' && !open.empty()) {
      if (open.back().array) ++open.back().index;
      else open.back().expect_key = true;
    }
    i += n;
  }
}

// Where the parser is, from its callback: a duplicate key, or a number that
// does not fit, is reported at this pointer.
struct ParsePosition {
  struct Level {
    bool array = false;
    std::size_t elements = 0;  // arrays: elements begun so far
    std::string key;
    std::set<std::string> keys;
  };
  std::vector<Level> levels;

  // The pointer of the value being read now (the next element in an array).
  std::string pointer() const {
    std::string path;
    for (const Level& l : levels)
      path = l.array ? JsonReader::at(path, l.elements == 0 ? 0 : l.elements - 1) : JsonReader::at(path, l.key);
    return path;
  }
  std::string pointer_of_failure() const {
    std::string path;
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const Level& l = levels[i];
      // The innermost array's failing element has not begun in the callback's eyes.
      const std::size_t element = i + 1 == levels.size() ? l.elements : (l.elements == 0 ? 0 : l.elements - 1);
      path = l.array ? JsonReader::at(path, element) : JsonReader::at(path, l.key);
    }
    return path;
  }
  void element_begins() {
    if (!levels.empty() && levels.back().array) ++levels.back().elements;
  }
};

}  // namespace

json parse_json_input(std::string_view text, const std::string& file, const JsonLimits& limits) {
  if (text.size() > limits.max_bytes)
    throw InputError(file, "", fmt::format("expected a JSON document of at most {} bytes, got {}", limits.max_bytes, text.size()));
  scan_bytes(text, file, limits);
  ParsePosition at;
  const json::parser_callback_t track = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        at.element_begins();
        at.levels.push_back({event == json::parse_event_t::array_start, 0, {}, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!at.levels.empty()) at.levels.pop_back();
        break;
      case json::parse_event_t::key: {
        ParsePosition::Level& l = at.levels.back();
        l.key = parsed.get<std::string>();
        if (!l.keys.insert(l.key).second)
          throw InputError(file, at.pointer(), "expected each key once in its object; \"" + l.key + "\" is there twice");
        break;
      }
      case json::parse_event_t::value:
        at.element_begins();
        break;
    }
    return true;
  };
  try {
    return json::parse(text, track);
  } catch (const json::parse_error& e) {
    std::string detail = e.what();
    std::size_t p = detail.find("column");
    if (p != std::string::npos && (p = detail.find(": ", p)) != std::string::npos) detail = detail.substr(p + 2);
    // A syntax error is placed by line and column: the pointer would only
    // name the value before it.
    throw InputError(file, "",
                     fmt::format("expected valid JSON; {}: {}", line_column(text, e.byte == 0 ? 0 : e.byte - 1), detail));
  } catch (const json::exception& e) {  // out_of_range 406: a number past a double's range
    throw InputError(file, at.pointer_of_failure(), std::string("expected a number a double holds (") + e.what() + ")");
  }
}

json read_json_input(const std::filesystem::path& file, const std::string& what, const JsonLimits& limits) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw InputError(file.string(), "", "expected " + what + " (cannot read it: " + ec.message() + ")");
  if (size > limits.max_bytes)
    throw InputError(file.string(), "", fmt::format("expected {} of at most {} bytes, got {}", what, limits.max_bytes, size));
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "", "expected " + what + " that is readable");
  std::stringstream text;
  text << in.rdbuf();
  return parse_json_input(text.str(), file.string(), limits);
}

}  // namespace gi
