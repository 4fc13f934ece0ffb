// Issue 19's acceptance scene end to end: the textured room (checker base
// colour, a normal-mapped wall, a metallic-roughness texture, an emissive
// texture; scenarios/assets/make_textured_room.py) matches Embree in
// reference mode, and the reference check fails when the realtime pipeline
// drops the normal map (textures.normal_map_decode none), passing on glTF's
// decode. Every Solari release's raw decode (Bevy #24880) touches ray hits
// only, not the G-buffer DI shades: the bug museum's mirror room catches it.
#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace gi {
namespace {

// A smaller, shorter run of a textured-room scenario, its glTF by absolute path.
std::filesystem::path small_variant(const std::string& scenario, const std::filesystem::path& dir,
                                    const std::string& name, const std::function<void(nlohmann::json&)>& edit) {
  return test::write_scenario_variant(scenario, dir, name + ".json", [&](nlohmann::json& doc) {
    doc["name"] = name;
    doc["scene"]["gltf"] = (test::source_dir() / "scenarios/assets/textured_room.gltf").string();
    doc["resolution"] = {80, 45};
    doc["frames"] = 16;
    for (nlohmann::json& c : doc["checks"])
      if (c["name"] == "reference") {
        c["frames"] = {15};
        c["spp"] = 128;
      }
    edit(doc);
  });
}

nlohmann::json run_reference_check(const std::filesystem::path& file, const std::filesystem::path& out) {
  const test::CommandResult r = test::run_giharness("run " + file.string() + " --out " + out.string());
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
  return test::check_result(out, "reference");
}

TEST(TexturedRoom, ReferenceModeMatchesEmbreeWithinNoise) {
  test::TempDir dir("textured_room_reference");
  const auto file = small_variant("scenarios/textured_room.json", dir.path(), "reference_mode", [](nlohmann::json&) {});
  const nlohmann::json c = run_reference_check(file, dir.path() / "out");
  EXPECT_EQ(c.value("verdict", ""), "pass") << c.dump();
}

TEST(TexturedRoom, TheReferenceCheckFailsWithoutTheNormalMapAndPassesWithIt) {
  test::TempDir dir("textured_room_normal_map");
  for (const std::string decode : {"signed", "none", "raw"}) {
    const bool drawn_right = decode != "none";  // raw: the G-buffer still decodes as glTF
    const auto file = small_variant("scenarios/textured_room_di.json", dir.path(), "decode_" + decode,
                                    [&](nlohmann::json& doc) { doc["overrides"]["textures.normal_map_decode"] = decode; });
    const nlohmann::json c = run_reference_check(file, dir.path() / ("out_" + decode));
    EXPECT_EQ(c.value("verdict", ""), drawn_right ? "pass" : "fail") << decode << ": " << c.dump();
  }
}

}  // namespace
}  // namespace gi
