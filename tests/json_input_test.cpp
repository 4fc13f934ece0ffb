// The guarded JSON reader (core/json_input.h): hostile documents are bad
// input (exit 2, file, JSON Pointer, line and column), never a crash or an
// internal error. The rows of the bad-input table, each through the binary, then
// each guard on its own.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/errors.h"
#include "core/json_input.h"
#include "tests/test_support.h"

namespace gi {
namespace {

void write_file(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
}

std::string nested_arrays(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

std::string tiny_scenario(const std::string& name, const std::string& scene, const std::string& extra = "") {
  return "{\"name\": \"" + name + "\", \"scene\": " + scene + ", \"resolution\": [8, 8], \"frames\": 1" + extra + "}";
}

// Runs the binary on the scenario; it must end as bad input, quoting `path`.
void expect_bad_input(const std::filesystem::path& scenario, const std::string& path, const std::string& also) {
  const test::CommandResult r = test::run_giharness("run " + scenario.string() + " --out " +
                                                    (scenario.parent_path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output.substr(0, 2000);
  EXPECT_NE(r.output.find(": " + path), std::string::npos) << r.output.substr(0, 2000);
  EXPECT_NE(r.output.find(also), std::string::npos) << r.output.substr(0, 2000);
}

TEST(JsonInput, ADescriptionNested60000DeepIsBadInput) {
  const test::TempDir dir("deep_scenario");
  const std::filesystem::path file = dir.path() / "deep.json";
  write_file(file, tiny_scenario("deep", "{\"generator\": \"cornell_box\"}", ", \"description\": " + nested_arrays(60000)));
  expect_bad_input(file, "/description/0/0", "nested at most 256 deep");
}

TEST(JsonInput, GltfExtrasNested100000DeepAreBadInput) {
  const test::TempDir dir("deep_gltf");
  write_file(dir.path() / "deep.gltf", "{\"asset\": {\"version\": \"2.0\", \"extras\": " + nested_arrays(100000) + "}}");
  const std::filesystem::path file = dir.path() / "scenario.json";
  write_file(file, tiny_scenario("deep_gltf", "{\"gltf\": \"deep.gltf\"}"));
  expect_bad_input(file, "/asset/extras/0", "nested at most 256 deep");
}

TEST(JsonInput, ANumberPastADoubleIsBadInputAtItsPath) {
  const test::TempDir dir("overflow");
  const std::filesystem::path file = dir.path() / "overflow.json";
  write_file(file, tiny_scenario("overflow", "{\"generator\": \"cornell_box\", \"params\": {\"light_scale\": 1e400}}"));
  expect_bad_input(file, "/scene/params/light_scale", "a number a double holds");
}

TEST(JsonInput, AKeyTwiceIsBadInputNamingIt) {
  const test::TempDir dir("duplicate");
  const std::filesystem::path file = dir.path() / "duplicate.json";
  write_file(file, tiny_scenario("duplicate", "{\"generator\": \"cornell_box\", \"generator\": \"cliff\"}"));
  expect_bad_input(file, "/scene/generator", "\"generator\" is there twice");
}

// ---- each guard on its own

std::string failure(const std::string& text, const JsonLimits& limits = {}) {
  try {
    parse_json_input(text, "t.json", limits);
  } catch (const InputError& e) {
    return e.json_path() + " | " + e.expected();
  }
  return "accepted";
}

TEST(JsonInput, DepthIsLimitedExactlyAndNamedByPointer) {
  const JsonLimits limits{.max_depth = 4};
  EXPECT_EQ(failure("{\"a\": [[[1]]]}", limits), "accepted");
  EXPECT_EQ(failure("{\"a\": [1, {\"b\": [[2]]}]}", limits),
            "/a/1/b/0 | expected arrays and objects nested at most 4 deep; deeper at line 1, column 18");
  // Brackets inside strings are text.
  EXPECT_EQ(failure("{\"a\": \"[[[[[[[[[[\"}", limits), "accepted");
  EXPECT_EQ(failure("{\"a\\\"[\": [[[1]]]}", limits), "accepted");
}

TEST(JsonInput, DuplicateKeysAreRefusedPerObject) {
  EXPECT_EQ(failure("{\"a\": {\"x\": 1}, \"b\": {\"x\": 2}}"), "accepted");  // one per object is fine
  EXPECT_EQ(failure("[{\"x\": 1}, {\"y\": 1, \"y\": 2}]"), "/1/y | expected each key once in its object; \"y\" is there twice");
  // The empty key too (found by the fuzzer: it used to slip through to the
  // plain parse, whose exception was uncaught).
  EXPECT_EQ(failure("{\"\": 1, \"\"x\"}"), "/ | expected each key once in its object; \"\" is there twice");
}

TEST(JsonInput, NumbersPastADoubleAreRefusedAtTheirElement) {
  EXPECT_EQ(failure("{\"a\": [1, 2, -1e400]}").substr(0, 33), "/a/2 | expected a number a double");
  EXPECT_EQ(failure("{\"a\": 1.7e308}"), "accepted");
}

TEST(JsonInput, BytesAreChecked) {
  EXPECT_EQ(failure("\xEF\xBB\xBF{}"), " | expected JSON without a byte-order mark (a UTF-8 BOM opens the file)");
  EXPECT_EQ(failure(std::string("{\"a\": \"x\0y\"}", 12)), "/a | expected no NUL byte; one at line 1, column 9");
  EXPECT_EQ(failure("{\"a\": \"\xC3\x28\"}"), "/a | expected valid UTF-8; an invalid byte at line 1, column 8");
  EXPECT_EQ(failure("{\"a\": \"\xED\xA0\x80\"}").substr(0, 26), "/a | expected valid UTF-8;");  // a surrogate
  EXPECT_EQ(failure("{\"a\": \"\xC3\xA9\xE2\x82\xAC\xF0\x9F\x98\x80\"}"), "accepted");        // é € 😀
  EXPECT_EQ(failure("{\"a\": 1}", JsonLimits{.max_bytes = 4}), " | expected a JSON document of at most 4 bytes, got 8");
}

TEST(JsonInput, SyntaxErrorsGiveLineAndColumn) {
  EXPECT_EQ(failure("{\n  \"a\": 1\n  \"b\": 2\n}").substr(0, 38), " | expected valid JSON; line 3, column");
}

TEST(JsonInput, AnUnreadableFileSaysWhatItShouldBe) {
  try {
    read_json_input("/nonexistent/x.json", "a scenario file");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/x.json");
    EXPECT_NE(std::string(e.what()).find("expected a scenario file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gi
