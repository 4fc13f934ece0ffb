// The light_leak check end to end on lavapipe: light where the path tracer has
// shadow. It fails on the bug it exists for (the world cache's query jitter
// keys cells past a 2 cm wall, Bevy #22252 under 0.18 and #24332 under 0.19:
// scenarios/bugs/bevy_22252_leak_through_thin_wall.json), passes on the fix
// (no jitter), and is refused without GI. Bevy's hit normals (world_cache.hit_normal
// "vertex") leak through a wall of one face: a back face keys its front's cell.
#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/npy.h"
#include "tests/test_support.h"

namespace gi {
namespace {

nlohmann::json leak(const std::filesystem::path& out) { return test::check_result(out, "light_leak"); }

double shadowed_ratio(const nlohmann::json& c) { return c["figures"]["max_shadowed_energy_ratio"].get<double>(); }

TEST(LightLeakCheck, JitteredCacheLeaksThroughAThinWallAndTheFixDoesNot) {
  test::TempDir dir("light_leak");
  const std::string scenario = (test::source_dir() / "scenarios/bugs/bevy_22252_leak_through_thin_wall.json").string();
  const auto bug = test::run_giharness("run " + scenario + " --out " + (dir.path() / "bug").string());
  EXPECT_EQ(bug.exit_code, 1) << bug.output;
  const nlohmann::json b = leak(dir.path() / "bug");
  EXPECT_EQ(b.at("verdict"), "fail");
  EXPECT_GT(shadowed_ratio(b), 1.5);
  // The region and both images as evidence, for a person to look at.
  ASSERT_EQ(b["evidence"].size(), 1u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "bug" / b["evidence"][0].get<std::string>()));

  const auto fix = test::run_giharness("run " + scenario + " --set world_cache.query_jitter=none --out " +
                                       (dir.path() / "fix").string());
  EXPECT_EQ(fix.exit_code, 0) << fix.output;
  const nlohmann::json f = leak(dir.path() / "fix");
  EXPECT_EQ(f.at("verdict"), "pass");
  EXPECT_LT(shadowed_ratio(f), 1.0);
  // The region is the reference's, so both sides judge the same pixels.
  EXPECT_EQ(b["figures"]["frames"][0]["shadowed_pixels"], f["figures"]["frames"][0]["shadowed_pixels"]);
  EXPECT_GT(f["figures"]["frames"][0]["shadowed_pixels"].get<int>(), 1000);

  // 0.19's own jitter leaks too (#24332), less: about 1.15 of the path
  // tracer's energy, within the limit's noise margin at 8 chains, so the
  // check need not fail on it (docs/statistics.md). What stays true is that
  // it leaks more than the fix.
  const auto v019 = test::run_giharness("run " + scenario + " --profile solari-0.19 --out " +
                                        (dir.path() / "v019").string());
  const nlohmann::json n = leak(dir.path() / "v019");
  EXPECT_GT(shadowed_ratio(n), shadowed_ratio(f) + 0.1) << v019.output;
}

// The live world-cache cells on the plane z = 0 (the wall of one face), by
// which side their normal faces, from the capture of `frame`.
struct WallCells {
  std::size_t lit_side = 0;   // normal −z: the face's own normal, into the lit room
  std::size_t dark_side = 0;  // normal +z
};

WallCells wall_cells(const std::filesystem::path& out, std::uint32_t frame) {
  const std::filesystem::path dir = out / "captures" / fmt::format("frame_{:05}", frame);
  const NpyArray life = read_npy(dir / "world_cache.life.npy");
  const NpyArray geometry = read_npy(dir / "world_cache.geometry.npy");  // position xyzw, normal xyzw
  const auto* l = reinterpret_cast<const std::uint32_t*>(life.data.data());
  const auto* g = reinterpret_cast<const float*>(geometry.data.data());
  WallCells c;
  for (std::uint64_t i = 0; i < life.element_count(); ++i) {
    const float* cell = g + 8 * i;
    if (l[i] == 0 || std::abs(cell[2]) > 1e-3f) continue;
    if (cell[6] < -0.99f) ++c.lit_side;
    if (cell[6] > 0.99f) ++c.dark_side;
  }
  return c;
}

// Solari queries the cache at a ray hit with the hit's interpolated vertex
// normal, never flipped (v0.18.0 realtime/restir_gi.wgsl:116,
// world_cache_update.wgsl:43; scene/raytracing_scene_bindings.wgsl:199-201).
// A ray from the dark room that hits the back of a wall of one face keys the
// cell of its front, whose normal looks into the lit room and whose light is
// the lit room's: no cell on the wall faces the dark room, and the dark side
// is lit (the light_leak check fails). Keyed by the face normal facing the
// ray, the back has cells of its own and the check passes.
TEST(LightLeakCheck, BevysHitNormalKeysABackFaceIntoItsFrontsCellAndLeaks) {
  test::TempDir dir("light_leak_normals");
  const std::string scenario = (test::source_dir() / "scenarios/expected_failures/leak_zero_thickness_wall.json").string();
  const auto bevy = test::run_giharness("run " + scenario + " --capture 47 --out " + (dir.path() / "bevy").string());
  EXPECT_EQ(bevy.exit_code, 1) << bevy.output;
  const nlohmann::json b = leak(dir.path() / "bevy");
  EXPECT_EQ(b.at("verdict"), "fail");
  const WallCells bc = wall_cells(dir.path() / "bevy", 47);
  EXPECT_GT(bc.lit_side, 20u);
  EXPECT_EQ(bc.dark_side, 0u);

  const auto flipped = test::run_giharness("run " + scenario + " --set world_cache.hit_normal=face_toward_ray --capture 47 --out " +
                                           (dir.path() / "flipped").string());
  EXPECT_EQ(flipped.exit_code, 0) << flipped.output;
  const nlohmann::json f = leak(dir.path() / "flipped");
  EXPECT_EQ(f.at("verdict"), "pass");
  const WallCells fc = wall_cells(dir.path() / "flipped", 47);
  EXPECT_GT(fc.dark_side, 20u);
  EXPECT_GT(fc.lit_side, 20u);
  EXPECT_GT(shadowed_ratio(b), shadowed_ratio(f) + 0.3);
  // The same pixels judged on both sides.
  EXPECT_EQ(b["figures"]["frames"][0]["shadowed_pixels"], f["figures"]["frames"][0]["shadowed_pixels"]);
}

TEST(LightLeakCheck, RefusedWithoutGi) {
  test::TempDir dir("light_leak_bad");
  const auto file = test::write_scenario_variant("scenarios/leak_thin_wall.json", dir.path(), "no_gi.json",
                                                 [](nlohmann::json& doc) { doc["gi"] = false; });
  const auto r = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/checks/1"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
