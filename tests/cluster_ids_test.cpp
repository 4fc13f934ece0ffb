// The cluster_ids check (checks/cluster_ids_check.h) fires on the
// overflow it exists for: counted (no device) on the published 1042-cliff
// figure and on real DAGs, and rendered with a 12-bit ID where the decoded IDs
// start naming the wrong instance exactly at the named spawn.
#include <gtest/gtest.h>

#include "core/clusters/cluster_ids.h"
#include "core/errors.h"
#include "core/clusters/cluster_table.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "core/scenes/cliff.h"
#include "checks/cluster_ids_check.h"
#include "replay/run_scenario.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;
const fs::path kScenarios = gi::test::source_dir() / "scenarios";

gi::RunResult run(const gi::Scenario& s, const fs::path& out, std::optional<std::uint32_t> frames = std::nullopt) {
  gi::RunOptions o;
  o.out_dir = out;
  o.quiet = true;
  o.frames = frames;
  return gi::run_scenario(s, o);
}

TEST(ClusterIds, PackingKeepsOnlyTheLowClusterBits) {
  using namespace gi::shader;
  EXPECT_EQ(cluster_pack(5, 3, 25, 7), (5u << 7) | 3u);
  EXPECT_EQ(cluster_unpack_id(cluster_pack(33554431u, 127, 25, 7), 25, 7), 33554431u);
  // 2^25 + 15682 (the published overshoot) aliases cluster 15682.
  EXPECT_EQ(cluster_unpack_id(cluster_pack(33554432u + 15682u, 0, 25, 7), 25, 7), 15682u);
  EXPECT_EQ(cluster_unpack_id(cluster_pack(4096u + 7u, 1, 12, 7), 12, 7), 7u);
}

// Count only, no device: 1041 cliffs of 32 217 clusters fit in 25 bits, the
// 1042nd is named (frame, event, totals).
TEST(ClusterIds, CountOnlyNamesThePublishedOverflowingSpawn) {
  gi::test::TempDir dir("cluster_ids_published");
  const gi::RunResult fail = run(gi::load_scenario(kScenarios / "expected_failures/cluster_ids_published_overflow.json"),
                                 dir.path() / "a");
  ASSERT_EQ(fail.exit_code, 1);
  const nlohmann::json& f = fail.checks.at(0).figures;
  EXPECT_EQ(f["overflow"]["instance"], "cliff_1042");
  EXPECT_EQ(f["overflow"]["ids_before"], 33537897u);   // 1041 × 32 217
  EXPECT_EQ(f["overflow"]["ids_after"], 33570114u);    // 1042 × 32 217
  EXPECT_EQ(f["overflow"]["limit"], 33554432u);        // 2^25
  EXPECT_EQ(f["overflow"]["spawn_number"], 1041u);     // the scene's own cliff is the first
  EXPECT_EQ(f["overflow"]["frame"], 1041u);
  // One repeated spawn event stands for all 1041 (its path; the instance names the one).
  EXPECT_EQ(f["overflow"]["event"], "/events/0");
  EXPECT_EQ(fail.checks[0].first_failing_frame, 1041u);
  EXPECT_TRUE(fs::exists(dir.path() / "a/summary.json"));
  const gi::RunResult pass = run(gi::load_scenario(kScenarios / "cluster_ids_1041_cliffs.json"), dir.path() / "b");
  EXPECT_EQ(pass.exit_code, 0) << pass.checks.at(0).message;
  EXPECT_EQ(pass.checks[0].figures["peak_ids"], 33537897u);
}

// Count only on real DAGs: the named spawn is the first whose DAG clusters
// push the total past 2^bits; a despawn frees its IDs.
TEST(ClusterIds, CountOnlyUsesEachMeshsDagAndDespawnsFreeIds) {
  nlohmann::json doc = {{"name", "count"},
                        {"scene", {{"generator", "cliff"}, {"params", {{"triangles", 3000}}}}},
                        {"resolution", {8, 8}},
                        {"frames", 10},
                        {"events", nlohmann::json::array()},
                        {"checks", {{{"name", "cluster_ids"}, {"cluster_bits", 8}, {"count_only", true}}}}};
  for (int k = 1; k <= 6; ++k)
    doc["events"].push_back({{"type", "spawn"}, {"frame", k}, {"instance", "c" + std::to_string(k)}, {"of", "cliff"}});
  const gi::Scenario s = gi::parse_scenario(doc, "count.json");
  const gi::Scene initial = gi::build_scene(s);
  const std::uint64_t per = gi::build_cluster_dag(initial.meshes[0]).clusters.size();
  ASSERT_LT(per, 256u);
  const std::uint64_t fitting = 256 / per;  // instances that fit
  ASSERT_LT(fitting, 7u);
  const gi::ClusterIdsCheck check(gi::cluster_ids_params(s.checks[0], s), s, initial, s.frames);
  ASSERT_TRUE(check.overflow());
  EXPECT_EQ(check.overflow()->spawn_number, fitting);  // instance fitting + 1
  EXPECT_EQ(check.overflow()->ids_after, (fitting + 1) * per);
  EXPECT_FALSE(check.result().passed());

  // Despawn one before each spawn past the first: never more than 2 stand.
  nlohmann::json churn = doc;
  churn["events"] = nlohmann::json::array();
  for (int k = 1; k <= 6; ++k) {
    churn["events"].push_back({{"type", "spawn"}, {"frame", k}, {"instance", "c" + std::to_string(k)}, {"of", "cliff"}});
    if (k > 1) churn["events"].push_back({{"type", "despawn"}, {"frame", k}, {"instance", "c" + std::to_string(k - 1)}});
  }
  const gi::Scenario c = gi::parse_scenario(churn, "churn.json");
  const gi::ClusterIdsCheck ok(gi::cluster_ids_params(c.checks[0], c), c, gi::build_scene(c), c.frames);
  EXPECT_FALSE(ok.overflow());
  EXPECT_TRUE(ok.result().passed()) << ok.result().message;
}

// A count-only cluster_ids check decides the run without drawing, so a check
// that needs drawn frames beside it is bad input at that check's name (exit
// 2), before any device is opened; alone it writes the run's summary.
TEST(ClusterIds, CountOnlyRefusesADrawnCheckBesideIt) {
  gi::test::TempDir dir("cluster_ids_count_only_alone");
  nlohmann::json doc = {{"name", "count_beside"},
                        {"scene", {{"generator", "cliff"}, {"params", {{"triangles", 3000}}}}},
                        {"resolution", {8, 8}},
                        {"frames", 4},
                        {"checks", {{{"name", "cluster_ids"}, {"count_only", true}}, {{"name", "finite"}}}}};
  try {
    run(gi::parse_scenario(doc, "count_beside.json"), dir.path() / "beside");
    ADD_FAILURE() << "a finite check beside a count-only cluster_ids check ran";
  } catch (const gi::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/checks/1/name"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("count-only"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir.path() / "beside/summary.json"));
  doc["checks"].erase(1);
  const gi::RunResult alone = run(gi::parse_scenario(doc, "count_alone.json"), dir.path() / "alone");
  EXPECT_EQ(alone.exit_code, 0) << alone.checks.at(0).message;
  const nlohmann::json summary = nlohmann::json::parse(gi::test::read_text(dir.path() / "alone/summary.json"));
  EXPECT_EQ(summary["resolved"]["mode"], "count_only");
}

// The CPU decode (what gbuffer_resolve.comp does) finds every drawn triangle
// again while IDs fit, and names another instance once they alias.
TEST(ClusterIds, TableDecodesEveryTriangleUntilIdsAlias) {
  gi::CliffOptions o;
  o.triangles = 2000;
  gi::Scene scene = gi::make_cliff_scene(o);
  gi::Instance second = scene.instances[0];
  second.name = "second";
  scene.instances.push_back(second);
  const gi::FlatGeometry g = gi::flatten_geometry(scene);
  const gi::FlatInstances flat = gi::flatten_instances(scene, g);
  const gi::ClusterDag dag = gi::build_cluster_dag(scene.meshes[0]);
  const std::vector<gi::MeshClusterIds> ids = {gi::dag_cluster_ids(dag, g, 0)};
  auto encode = [&](const std::vector<std::uint32_t>& t, std::uint32_t inst, std::uint32_t prim) {
    using namespace gi::shader;
    const std::uint32_t where = t[t[CT_PRIMITIVES] + flat.instances[inst].first_index / 3 + prim];
    return cluster_pack(t[t[CT_INSTANCES] + 4 * inst] + (where >> 8), where & 255u, t[CT_CLUSTER_BITS], t[CT_TRIANGLE_BITS]);
  };
  const std::uint32_t per = static_cast<std::uint32_t>(dag.clusters.size());
  for (std::uint32_t bits : {25u, 0u}) {
    gi::ClusterIdLayout layout;
    // 0: the first instance's drawn (LOD-0) IDs fit, the second's wrap:
    // lod0 ≤ 2^bits < per + lod0.
    layout.cluster_bits =
        bits ? bits : static_cast<std::uint32_t>(std::floor(std::log2(double(per + dag.lod0_clusters - 1))));
    const auto t = gi::build_cluster_table(g.meshes, g.indices.size() / 3, ids, flat.instances, {true, true}, layout);
    EXPECT_EQ(gi::cluster_ids_in_use(t), 2u * per);
    std::uint32_t wrong = 0;
    for (std::uint32_t inst = 0; inst < 2; ++inst)
      for (std::uint32_t p = 0; p < g.meshes[0].triangle_count; ++p) {
        const gi::DecodedVisibility d = gi::decode_packed_visibility(t, encode(t, inst, p));
        if (!d.valid || d.instance != inst || d.primitive != p) ++wrong;
      }
    if (bits) {
      EXPECT_EQ(wrong, 0u);
    } else {
      EXPECT_GT(wrong, 0u) << "aliased IDs must decode to the wrong place";
    }
  }
}

// Rendered with 12 cluster bits: the overflowing spawn is named before it is
// drawn; every frame before it has 0 decode mismatches; later frames have
// mismatches (the garbage the check exists to catch), and the variant
// that stops below the limit passes with 0 mismatches.
TEST(ClusterIds, RenderedSpawnsFlagTheOverflowBeforeAnyWrongPixel) {
  gi::test::TempDir dir("cluster_ids_rendered");
  const gi::Scenario s = gi::load_scenario(kScenarios / "expected_failures/cluster_ids_spawn_cliffs.json");
  const gi::RunResult r = run(s, dir.path() / "over", 14u);
  ASSERT_EQ(r.exit_code, 1);
  const gi::CheckResult& c = r.checks.back();
  ASSERT_EQ(c.name, "cluster_ids");
  ASSERT_TRUE(c.figures.contains("overflow")) << c.message;
  const std::uint32_t overflow_frame = c.figures["overflow"]["frame"];
  EXPECT_EQ(c.figures["decode_mismatches_before_overflow"], 0u);
  EXPECT_GT(c.figures["decode_mismatches"].get<std::uint64_t>(), 0u);
  // The named spawn's own LOD-0 IDs may still fit (only its upper levels
  // overflow); the first wrong pixel is never before it.
  EXPECT_GE(c.figures["first_mismatch_frame"].get<std::uint32_t>(), overflow_frame);
  // The rendered buffer alone names the spawn the walk named: the instance
  // most of the first wrong frame's pixels belong to.
  ASSERT_TRUE(c.figures.contains("rendered_overflow")) << c.message;
  const nlohmann::json& rendered = c.figures["rendered_overflow"];
  EXPECT_EQ(rendered["frame"], c.figures["first_mismatch_frame"]);
  EXPECT_EQ(rendered["spawn_number"], c.figures["overflow"]["spawn_number"]);
  EXPECT_EQ(rendered["instance"].get<std::string>().substr(0, 6), "cliff_");
  EXPECT_NE(c.message.find("the rendered buffer names spawn"), std::string::npos) << c.message;
  for (const nlohmann::json& f : r.summary["frames"]) {
    const std::uint32_t frame = f["frame"];
    EXPECT_EQ(f["cluster_ids"]["over_limit"], frame >= overflow_frame) << frame;
    if (frame < overflow_frame) {
      EXPECT_EQ(f["cluster_ids"]["decode_mismatches"], 0u) << frame;
    }
  }
  const gi::RunResult ok = run(gi::load_scenario(kScenarios / "cluster_ids_cliffs_below_limit.json"), dir.path() / "ok");
  EXPECT_EQ(ok.exit_code, 0) << ok.checks.back().message;
  EXPECT_EQ(ok.checks.back().figures["decode_mismatches"], 0u);
}

}  // namespace
