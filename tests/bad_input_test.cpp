// Every class of bad input, as a script meets it: `giharness run` exits 2 and
// its message names the file and the JSON path (list). The unit
// tests beside the parsers check the same errors in more depth; this holds the
// contract at the command line, where a nightly meets it.
#include <gtest/gtest.h>

#include <fstream>
#include <limits>

#include "core/errors.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "replay/resource_limits.h"
#include "tests/gltf_fixture.h"
#include "tests/test_support.h"

namespace gi {
namespace {

using nlohmann::json;
using test::TinyGltf;

struct Expect {
  std::string file;       // must appear in the message
  std::string json_path;  // must appear in the message
};

void expect_exit_two(const std::filesystem::path& scenario, const Expect& e) {
  test::TempDir out("bad-input-out");
  const test::CommandResult r = test::run_giharness("run " + scenario.string() + " --out " + out.path().string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(e.file), std::string::npos) << "file " << e.file << " not named in: " << r.output;
  EXPECT_NE(r.output.find(e.json_path), std::string::npos) << "path " << e.json_path << " not named in: " << r.output;
  EXPECT_FALSE(std::filesystem::exists(out.path() / "summary.json")) << "no result for bad input";
}

// Scenario files (tests/data/scenarios/bad/).
void expect_bad_scenario(const char* name, const char* json_path) {
  const auto file = test::source_dir() / "tests/data/scenarios/bad" / name;
  expect_exit_two(file, {name, json_path});
}

TEST(BadInput, MalformedJson) { expect_bad_scenario("malformed_json.json", "line 5"); }
TEST(BadInput, WrongType) { expect_bad_scenario("wrong_type.json", "/frames"); }
TEST(BadInput, OutOfRangeValue) { expect_bad_scenario("out_of_range.json", "/resolution/1"); }
TEST(BadInput, UnknownKey) { expect_bad_scenario("unknown_key.json", "/events/0/translate"); }
TEST(BadInput, MissingSceneFile) { expect_bad_scenario("missing_scene_file.json", "/scene/gltf"); }
// A check parameter the parser accepts but the run refuses: a warm-up that
// would start the reference window after the compared frame.
TEST(BadInput, WarmupPastTheComparedFrame) {
  test::TempDir dir("warmup");
  const auto file = dir.path() / "warmup_past_compared_frame.json";
  std::ofstream(file) << R"({"name": "warmup", "scene": {"generator": "cornell_box"}, "resolution": [16, 16],
                             "frames": 8, "mode": "realtime",
                             "checks": [{"name": "reference", "frames": [4], "warmup_frames": 6}]})";
  expect_exit_two(file, {"warmup_past_compared_frame.json", "/checks/0/warmup_frames"});
}

// A capture frame the scenario's own run never reaches is the file's mistake
// (exit 2 at /capture/0), not a --frames matter (tests/cli_test.cpp: a run
// shortened by --frames skips the later captures with a warning).
TEST(BadInput, CaptureFramePastTheScenariosFrames) {
  test::TempDir dir("capture-past-frames");
  const auto file = dir.path() / "capture_past_frames.json";
  std::ofstream(file) << R"({"name": "late_capture", "scene": {"generator": "cornell_box"}, "resolution": [16, 16],
                             "frames": 8, "mode": "reference", "capture": [999]})";
  expect_exit_two(file, {"capture_past_frames.json", "/capture/0"});
  try {
    load_scenario(file);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/capture/0");
    EXPECT_NE(e.expected().find("below \"frames\" (8)"), std::string::npos) << e.what();
  }
  // The last frame is a frame of the run.
  std::ofstream(file) << R"({"name": "last_capture", "scene": {"generator": "cornell_box"}, "resolution": [16, 16],
                             "frames": 8, "mode": "reference", "capture": [7]})";
  EXPECT_NO_THROW(load_scenario(file));
}

TEST(BadInput, MissingScenarioFile) {
  expect_exit_two("/nonexistent/giharness/scenario.json", {"/nonexistent/giharness/scenario.json", ":"});
}

// glTF scenes: a scenario pointing at a glTF broken in one place.
class BadGltf : public ::testing::Test {
 protected:
  test::TempDir dir_{"bad-gltf"};

  void expect_bad(const json& gltf, const std::string& json_path) {
    const auto file = dir_.path() / "scene.gltf";
    std::ofstream(file) << gltf.dump(1);
    const auto scenario = dir_.path() / "scenario.json";
    std::ofstream(scenario) << R"({"name": "bad_gltf", "scene": {"gltf": "scene.gltf"}, "resolution": [16, 16],
                                  "frames": 1, "mode": "reference"})";
    expect_exit_two(scenario, {file.string(), json_path});
  }
};

TEST_F(BadGltf, IndexOutOfRange) {
  TinyGltf t;
  t.indices = {0, 1, 7};
  expect_bad(t.doc(), "/meshes/0/primitives/0/indices");
}

TEST_F(BadGltf, MissingBuffer) {
  json d = TinyGltf{}.doc();
  d["buffers"][0]["uri"] = "not_there.bin";
  expect_bad(d, "/buffers/0/uri");
}

TEST_F(BadGltf, NanInVertices) {
  TinyGltf t;
  t.positions[2] = std::numeric_limits<float>::quiet_NaN();
  expect_bad(t.doc(), "/accessors/0");
}

TEST_F(BadGltf, InfInVertices) {
  TinyGltf t;
  t.positions[6] = -std::numeric_limits<float>::infinity();
  expect_bad(t.doc(), "/accessors/0");
}

TEST_F(BadGltf, NonFiniteTransform) {
  // JSON cannot spell NaN; 1e39 is a finite double but no 32-bit float.
  json d = TinyGltf{}.doc();
  d["nodes"][0]["scale"] = {1.0, 1e39, 1.0};
  expect_bad(d, "/nodes/0/scale");
}

TEST_F(BadGltf, ZeroAreaEmitter) {
  TinyGltf t;
  t.positions = {0, 0, 0, 1, 1, 1, 2, 2, 2};  // collinear: no area
  json d = t.doc();
  d["materials"] = json::array({{{"emissiveFactor", {1, 1, 1}}}});
  d["meshes"][0]["primitives"][0]["material"] = 0;
  expect_bad(d, "/nodes/0");
}

TEST_F(BadGltf, EmptyScene) {
  json d = TinyGltf{}.doc();
  d["scenes"][0]["nodes"] = json::array();
  expect_bad(d, "/scenes/0");
}

TEST_F(BadGltf, RecursiveNodes) {
  json d = TinyGltf{}.doc();
  d["nodes"][0]["children"] = {0};
  expect_bad(d, "/nodes/0/children/0");
}

}  // namespace
}  // namespace gi

namespace gi {
namespace {

// Limits: a resolution the parser accepts (8192x8192) but whose buffers would
// not fit the device's memory is bad input naming /resolution, checked before
// anything is allocated.
TEST(BadInput, ScenarioTooLargeForTheDevice) {
  test::TempDir dir("too-large");
  const auto file = dir.path() / "huge.json";
  std::ofstream(file) << R"({"name": "huge", "scene": {"generator": "cornell_box"}, "resolution": [8192, 8192],
                             "frames": 1, "mode": "reference"})";
  const Scenario scenario = load_scenario(file);
  const Scene scene = build_scene(scenario);
  const std::uint64_t need = estimated_gpu_bytes(scenario, scene);
  EXPECT_GT(need, 16ull << 30);  // 8192² pixels at well over 256 B each: more than 16 GiB
  try {
    check_resource_limits(scenario, scene, need - 1);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/resolution");
    EXPECT_NE(std::string(e.what()).find("huge.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("MiB"), std::string::npos);
  }
  EXPECT_NO_THROW(check_resource_limits(scenario, scene, need));
}

TEST(BadInput, TooManyLightTriangles) {
  test::TempDir dir("many-lights");
  const auto file = dir.path() / "lights.json";
  std::ofstream(file) << R"({"name": "lights", "scene": {"generator": "cornell_box"}, "resolution": [8, 8],
                             "frames": 1, "mode": "reference"})";
  const Scenario scenario = load_scenario(file);
  Scene scene = build_scene(scenario);
  Mesh& light = scene.meshes[scene.instances[*scene.find_instance("light")].mesh];
  light.indices.resize((kMaxLights + 1) * 3, 0);  // counted, never rendered
  try {
    check_resource_limits(scenario, scene, 0);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/scene");
    EXPECT_NE(std::string(e.what()).find("light"), std::string::npos);
  }
}

}  // namespace
}  // namespace gi

namespace gi {
namespace {

// Texels live in one storage buffer: more than the device's
// maxStorageBufferRange is bad input before any upload.
TEST(BadInput, TexturesLargerThanOneStorageBuffer) {
  test::TempDir dir("large-textures");
  const auto file = dir.path() / "textures.json";
  std::ofstream(file) << R"({"name": "textures", "scene": {"generator": "cornell_box"}, "resolution": [8, 8],
                             "frames": 1, "mode": "reference"})";
  const Scenario scenario = load_scenario(file);
  Scene scene = build_scene(scenario);
  TextureImage image;
  image.width = image.height = 1024;
  image.rgba.assign(std::size_t(1024) * 1024 * 4, 255);
  scene.images.push_back(image);
  scene.images.push_back(image);
  EXPECT_EQ(texel_bytes(scene), 8ull << 20);
  EXPECT_GE(estimated_gpu_bytes(scenario, scene), 8ull << 20);
  try {
    check_resource_limits(scenario, scene, 0, (8ull << 20) - 1);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/scene");
    EXPECT_NE(std::string(e.what()).find("maxStorageBufferRange"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(check_resource_limits(scenario, scene, 0, 8ull << 20));
}

}  // namespace
}  // namespace gi
