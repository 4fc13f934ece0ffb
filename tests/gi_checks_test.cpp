// The `jacobian` and `finite` checks on ReSTIR GI and specular GI,
// end to end through the giharness binary, each shown to fire on the bug it
// exists for and to pass on the fixed pipeline:
// - jacobian: gi_corners passes under 0.18 (rejection above 1.2); with the
//   rejection switched off it fails and names the first frame;
// - finite: the zero-roughness mirror stays finite with 0.18's roughness clamp
//   and turns NaN without it (the 0.17 state);
// - the reuse jacobian of a sample on a back face: 0 under Solari's sample
//   normal (restir_gi.sample_normal "shading"), finite under the flipped one.
// Small runs (64×64, a few frames) on lavapipe.
#include <gtest/gtest.h>

#include <fstream>

#include <fmt/format.h>

#include "core/npy.h"
#include "test_support.h"

namespace gi {
namespace {

using GiRun = test::ScenarioRun;

GiRun run_scenario_file(const std::string& scenario, const std::string& extra, const std::string& tag) {
  test::TempDir dir("gi_" + tag);
  const auto r = test::run_giharness("run " + (test::source_dir() / "scenarios" / scenario).string() + " " + extra +
                                     " --out " + dir.path().string());
  return {r.exit_code, r.output, test::read_json(dir.path() / "summary.json")};
}

nlohmann::json check(const GiRun& r, const std::string& name) {
  for (const auto& c : r.summary["checks"])
    if (c["name"] == name) return c;
  ADD_FAILURE() << "no check " << name << " in " << r.output;
  return {};
}

// gi/stats's count of raw jacobians that were inf or NaN (GiStats, word 3) in
// the capture of `frame`.
std::uint32_t nonfinite_jacobians(const std::filesystem::path& out, std::uint32_t frame) {
  const NpyArray stats = read_npy(out / "captures" / fmt::format("frame_{:05}", frame) / "gi.stats.npy");
  return reinterpret_cast<const std::uint32_t*>(stats.data.data())[3];
}

// Solari's GI sample keeps its hit's shading normal, unflipped (v0.18.0
// realtime/restir_gi.wgsl:108), and its jacobian saturates both cosines
// (:206-207): from a sample on the back of a wall of one face every
// receiver is behind the normal, J = 0/0 and the merge is refused. With the
// normal flipped towards the ray that found the sample, J is finite there.
TEST(GiJacobianCheck, SolarisSampleNormalGivesBackFaceSamplesNoJacobian) {
  test::TempDir dir("gi_sample_normal");
  const auto file = test::write_scenario_variant(
      "scenarios/expected_failures/leak_zero_thickness_wall.json", dir.path(), "short.json", [](nlohmann::json& doc) {
        doc["frames"] = 6;
        doc["checks"] = nlohmann::json::array({{{"name", "finite"}}});
      });
  auto run = [&](const std::string& sets, const std::string& tag) {
    const auto r = test::run_giharness("run " + file.string() + " --capture 5 " + sets + " --out " +
                                       (dir.path() / tag).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nonfinite_jacobians(dir.path() / tag, 5);
  };
  const std::uint32_t solari = run("", "solari");
  const std::uint32_t flipped = run("--set restir_gi.sample_normal=face_toward_ray", "flipped");
  EXPECT_GT(solari, 100u);
  EXPECT_LT(flipped * 20, solari) << "flipped " << flipped << ", Solari's " << solari;
}

TEST(GiJacobianCheck, CornersPassWithRejectionAndFailWithoutNamingTheFrame) {
  const GiRun good = run_scenario_file("gi_corners.json", "--frames 6", "corners");
  const nlohmann::json j = check(good, "jacobian");
  ASSERT_EQ(good.exit_code, 0) << j.dump(1) << good.output;
  EXPECT_GT(j["figures"]["merges"].get<std::uint64_t>(), 0u);
  EXPECT_GT(j["figures"]["rejections"].get<std::uint64_t>(), 0u) << "the corners must make rejection work";
  EXPECT_LE(j["figures"]["max_accepted_j"].get<double>(), double(1.2f));
  EXPECT_EQ(j["figures"]["nonfinite_reservoirs"].get<std::uint64_t>(), 0u);
  // Per-frame statistics are in the frame records, timings for every GI pass.
  EXPECT_TRUE(good.summary["frames"][0].contains("gi"));
  for (const char* pass : {"gi_initial_temporal", "gi_spatial_shade", "specular_gi"})
    EXPECT_TRUE(good.summary["timings"]["passes"].contains(pass)) << pass << " " << good.summary["timings"].dump();

  const GiRun bad = run_scenario_file("expected_failures/gi_corners_no_jacobian_rejection.json", "--frames 6", "corners_bad");
  const nlohmann::json b = check(bad, "jacobian");
  ASSERT_EQ(bad.exit_code, 1) << bad.output;
  ASSERT_TRUE(b["first_failing_frame"].is_number()) << b.dump(1);
  EXPECT_GT(b["figures"]["max_accepted_j"].get<double>(), 1.2);
  EXPECT_EQ(b["figures"]["rejections"].get<std::uint64_t>(), 0u);
  const std::string message = b["message"].get<std::string>();
  EXPECT_NE(message.find(fmt::format("frame {}:", b["first_failing_frame"].get<int>())), std::string::npos) << message;
  EXPECT_NE(message.find("above 1.2"), std::string::npos) << message;
}

TEST(GiFiniteCheck, HardCasesAreFiniteWithTheClampAndZeroRoughnessIsNaNWithout) {
  const GiRun clamped = run_scenario_file("gi_hard_cases.json", "--frames 3", "mirror_clamped");
  const nlohmann::json f = check(clamped, "finite");
  EXPECT_EQ(f["verdict"], "pass") << f.dump(1) << clamped.output;
  EXPECT_EQ(f["figures"]["nonfinite_pixels"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(f["figures"]["nonfinite_gi_reservoirs_and_output"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(clamped.exit_code, 0) << check(clamped, "jacobian").dump(1);  // the other hard cases too

  const GiRun unclamped = run_scenario_file("expected_failures/gi_zero_roughness_no_clamp.json", "--frames 3", "mirror_unclamped");
  const nlohmann::json u = check(unclamped, "finite");
  ASSERT_EQ(unclamped.exit_code, 1) << unclamped.output;
  EXPECT_EQ(u["verdict"], "fail");
  EXPECT_EQ(u["first_failing_frame"], 0) << u.dump(1);
  EXPECT_GT(u["figures"]["nonfinite_gi_reservoirs_and_output"].get<std::uint64_t>(), 0u);
}

TEST(GiScenario, JacobianCheckWithoutGiIsBadInput) {
  test::TempDir dir("gi_bad_input");
  nlohmann::json doc = test::read_json(test::source_dir() / "scenarios" / "gi_corners.json");
  doc.erase("gi");
  doc["$schema"] = (test::source_dir() / "scenarios" / "schema.json").string();
  const auto file = dir.path() / "no_gi.json";
  {
    std::ofstream(file) << doc.dump(2);
  }
  const auto out = test::run_giharness("run " + file.string() + " --out " + (dir.path() / "out").string());
  EXPECT_EQ(out.exit_code, 2) << out.output;
  EXPECT_NE(out.output.find("/checks/1/name"), std::string::npos) << out.output;
}

// ReSTIR GI and specular GI terminating in the world cache (restir_gi.hit_radiance
// world_cache, docs/design.md §3 step 7): the full realtime image of the Cornell box
// keeps its energy against the Embree full-GI reference, and the cache is
// alive (the GI passes' pixel-rooted queries insert and refresh cells).
TEST(GiWorldCache, CornellBoxEnergyWithinFivePercentAndCacheCellsActive) {
  const GiRun r = run_scenario_file(
      "gi_cornell_box.json", "--set restir_gi.hit_radiance=world_cache --set world_cache.cells=65536", "cornell_wc");
  const nlohmann::json ref = check(r, "reference");
  ASSERT_TRUE(ref.contains("figures")) << r.output;
  const nlohmann::json last = ref["figures"]["frames"].back();
  const double energy = last["temporal_mean"]["energy_ratio"].get<double>();
  EXPECT_NEAR(energy, 1.0, 0.05) << last.dump(1);
  EXPECT_EQ(check(r, "finite")["verdict"], "pass") << r.output;
  const nlohmann::json& frames = r.summary["frames"];
  ASSERT_FALSE(frames.empty());
  for (const auto& f : frames) ASSERT_TRUE(f.contains("world_cache")) << f.dump(1);
  EXPECT_GT(frames.back()["world_cache"]["active_cells"].get<std::uint64_t>(), 0u) << frames.back().dump(1);
  EXPECT_GT(frames.back()["world_cache"]["live_cells"].get<std::uint64_t>(), 0u);
  EXPECT_TRUE(r.summary["timings"]["passes"].contains("world_cache_commit")) << r.summary["timings"].dump();
}

// Solari's world cache shades every secondary hit as diffuse with its full
// base colour (brdf.secondary_hits "diffuse"): light reaching the mirror
// scene's floor and walls by way of the mirror is scattered instead of
// reflected. "full" follows glossy hits along their BRDF before the path ends
// in the cache. Both within 6 % of Embree (the scenario's tolerance, widened
// by 0.18's material model), and within 2 % of each other: until the cache's
// own bounce took the base colour of metals (2026-12-04) the diffuse state
// was 0.906 against full's 0.948; now 0.942. The window starts after
// warmup_frames, so the cache's warm-up is not what is judged.
TEST(GiWorldCache, MirrorSceneDiffuseSecondaryHitsWithinTwoPercentOfFull) {
  const GiRun full = run_scenario_file("gi_mirror.json", "", "mirror_full");
  const nlohmann::json ok = check(full, "reference");
  ASSERT_TRUE(ok.contains("figures")) << full.output;
  const nlohmann::json last = ok["figures"]["frames"].back();
  EXPECT_EQ(ok["verdict"], "pass") << last.dump(1);
  const double full_energy = last["temporal_mean"]["energy_ratio"].get<double>();
  EXPECT_NEAR(full_energy, 1.0, 0.06) << last.dump(1);
  EXPECT_EQ(last["window_start"].get<int>(), 64) << "warmup_frames must start the window at frame 64";
  EXPECT_EQ(last["window_frames"].get<int>(), 64);
  EXPECT_EQ(full.exit_code, 0) << full.output;

  const GiRun diffuse = run_scenario_file("gi_mirror.json", "--set brdf.secondary_hits=diffuse", "mirror_diffuse");
  const nlohmann::json bevy = check(diffuse, "reference");
  ASSERT_TRUE(bevy.contains("figures")) << diffuse.output;
  EXPECT_EQ(bevy["verdict"], "pass") << bevy.dump(1);
  const double diffuse_energy = bevy["figures"]["frames"].back()["temporal_mean"]["energy_ratio"].get<double>();
  EXPECT_NEAR(diffuse_energy, full_energy, 0.02) << "the cache's bounce must weigh a metal by its base colour";
  EXPECT_LT(diffuse_energy, full_energy + 0.005) << "diffuse secondary hits add no light that full misses";
}

}  // namespace
}  // namespace gi
