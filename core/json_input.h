// Every JSON document a person or another tool wrote (scenarios, profiles,
// capture manifests, glTF) is read through here, so hostile input meets one
// set of guards before any parser recurses into it:
// - a size limit, checked before the file is read;
// - no byte-order mark, no NUL byte, valid UTF-8 throughout;
// - a nesting-depth limit, checked by a scan of the bytes that does not
//   recurse (a 60 000-deep array overflowed the stack of the parsers and the
//   walkers after them);
// - numbers that fit a double (1e400 is bad input, not an internal error);
// - no key twice in one object (a hand-written duplicate is a mistake, and
//   which value wins is the parser's accident).
// Each failure is an InputError (exit 2) naming the file, the JSON Pointer of
// the value where it is known, and the line and column.
#pragma once
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace gi {

struct JsonLimits {
  std::size_t max_bytes = std::size_t(256) << 20;  // a glTF's JSON chunk may be large; scenarios are KBs
  std::size_t max_depth = 256;                     // arrays and objects nested in one another
};

// The document `text` of `file` (the name the errors give), checked as above.
nlohmann::json parse_json_input(std::string_view text, const std::string& file, const JsonLimits& limits = {});

// Reads and parses `file`; `what` says what it should be ("a scenario file").
nlohmann::json read_json_input(const std::filesystem::path& file, const std::string& what,
                               const JsonLimits& limits = {});

}  // namespace gi
