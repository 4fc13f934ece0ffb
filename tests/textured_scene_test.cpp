// The textured acceptance scene end to end: the textured room (checker base
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
    doc.erase("capture");  // the scenario's capture is of its frame 31
    for (nlohmann::json& c : doc["checks"])
      if (c["name"] == "reference") {
        c["frames"] = {15};
        c["spp"] = 128;
      }
    edit(doc);
  });
}

// Runs the variant and returns its reference check's result. The scenarios
// hold the finite and the reference checks: the run exits 0 when the reference
// check is to pass (`reference_passes`) and 1 when it is to fail, and the
// finite check passes either way.
nlohmann::json run_reference_check(const std::filesystem::path& file, const std::filesystem::path& out,
                                   bool reference_passes) {
  const test::CommandResult r = test::run_giharness("run " + file.string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, reference_passes ? 0 : 1) << r.output;
  EXPECT_EQ(test::check_result(out, "finite").value("verdict", ""), "pass") << file;
  return test::check_result(out, "reference");
}

TEST(TexturedRoom, ReferenceModeMatchesEmbreeWithinNoise) {
  test::TempDir dir("textured_room_reference");
  const auto file = small_variant("scenarios/textured_room.json", dir.path(), "reference_mode", [](nlohmann::json&) {});
  const nlohmann::json c = run_reference_check(file, dir.path() / "out", true);
  EXPECT_EQ(c.value("verdict", ""), "pass") << c.dump();
}

TEST(TexturedRoom, TheReferenceCheckFailsWithoutTheNormalMapAndPassesWithIt) {
  test::TempDir dir("textured_room_normal_map");
  for (const std::string decode : {"signed", "none", "raw"}) {
    const bool drawn_right = decode != "none";  // raw: the G-buffer still decodes as glTF
    const auto file = small_variant("scenarios/textured_room_di.json", dir.path(), "decode_" + decode,
                                    [&](nlohmann::json& doc) { doc["overrides"]["textures.normal_map_decode"] = decode; });
    const nlohmann::json c = run_reference_check(file, dir.path() / ("out_" + decode), drawn_right);
    EXPECT_EQ(c.value("verdict", ""), drawn_right ? "pass" : "fail") << decode << ": " << c.dump();
  }
}

}  // namespace
}  // namespace gi
