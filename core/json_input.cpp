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

// A SAX pass before the DOM is built: it knows where it is, so a duplicate
// key, or a number that does not fit, is reported at its JSON Pointer.
// (nlohmann's DOM parser with a callback would do both in one pass, but its
// end_object scans the enclosing container: quadratic in an array of 20 000
// objects, 52 s under the fuzzer's sanitizers.)
struct PositionTracker {
  struct Level {
    bool array = false;
    std::size_t elements = 0;  // arrays: elements begun so far
    std::string key;
    std::set<std::string> keys;
  };
  std::vector<Level> levels;
  bool has_duplicate = false;
  std::string duplicate;  // the first key found twice (may be "")
  std::string duplicate_at;
  int error_id = 0;  // nlohmann's exception id (101.. parse errors, 406 a number out of range)
  std::size_t error_byte = 0;
  std::string error_text;
  std::string error_at;

  // The pointer of the value being read now; `begun`: the innermost array's
  // current element has been counted (a started value) or not (a failure
  // inside the number that would have been it).
  std::string pointer(bool begun) const {
    std::string path;
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const Level& l = levels[i];
      const bool innermost = i + 1 == levels.size();
      const std::size_t element = innermost && !begun ? l.elements : (l.elements == 0 ? 0 : l.elements - 1);
      path = l.array ? JsonReader::at(path, element) : JsonReader::at(path, l.key);
    }
    return path;
  }
  bool value() {
    if (!levels.empty() && levels.back().array) ++levels.back().elements;
    return true;
  }
  bool open(bool array) {
    value();
    levels.push_back({array, 0, {}, {}});
    return true;
  }
  bool close() {
    levels.pop_back();
    return true;
  }

  bool null() { return value(); }
  bool boolean(bool) { return value(); }
  bool number_integer(json::number_integer_t) { return value(); }
  bool number_unsigned(json::number_unsigned_t) { return value(); }
  bool number_float(json::number_float_t, const std::string&) { return value(); }
  bool string(std::string&) { return value(); }
  bool binary(json::binary_t&) { return value(); }
  bool start_object(std::size_t) { return open(false); }
  bool start_array(std::size_t) { return open(true); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(std::string& k) {
    Level& l = levels.back();
    l.key = k;
    if (!l.keys.insert(k).second) {
      has_duplicate = true;
      duplicate = k;
      duplicate_at = pointer(true);
      return false;  // stops the pass
    }
    return true;
  }
  bool parse_error(std::size_t byte, const std::string&, const nlohmann::detail::exception& e) {
    error_id = e.id;
    error_byte = byte;
    error_text = e.what();
    error_at = pointer(false);
    return false;
  }
};

}  // namespace

json parse_json_input(std::string_view text, const std::string& file, const JsonLimits& limits) {
  if (text.size() > limits.max_bytes)
    throw InputError(file, "", fmt::format("expected a JSON document of at most {} bytes, got {}", limits.max_bytes, text.size()));
  scan_bytes(text, file, limits);
  PositionTracker at;
  json::sax_parse(text, &at);
  if (at.has_duplicate)
    throw InputError(file, at.duplicate_at, "expected each key once in its object; \"" + at.duplicate + "\" is there twice");
  if (at.error_id == 406)  // out_of_range: a number past a double's range
    throw InputError(file, at.error_at, "expected a number a double holds (" + at.error_text + ")");
  if (at.error_id != 0) {
    // A syntax error is placed by line and column: the pointer would only
    // name the value before it.
    std::string detail = at.error_text;
    std::size_t p = detail.find("column");
    if (p != std::string::npos && (p = detail.find(": ", p)) != std::string::npos) detail = detail.substr(p + 2);
    throw InputError(file, "",
                     fmt::format("expected valid JSON; {}: {}", line_column(text, at.error_byte == 0 ? 0 : at.error_byte - 1),
                                 detail));
  }
  try {
    return json::parse(text);
  } catch (const json::exception& e) {  // the SAX pass saw it all; this would be a bug of ours
    throw InputError(file, "", std::string("expected valid JSON (") + e.what() + ")");
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
