// Cluster DAG (core/clusters/cluster_dag.h) on the procedural cliff
// (core/scenes/cliff.h). Small meshes only: the 1 M-triangle figures come from
// `giharness clusters cliff:triangles=1000000` (README, "Virtual geometry").
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include <tbb/global_control.h>

#include "core/clusters/cluster_dag.h"
#include "core/scenes/cliff.h"

namespace {

gi::Mesh cliff(std::uint32_t triangles) {
  gi::CliffOptions o;
  o.triangles = triangles;
  return gi::make_cliff_mesh(o);
}

TEST(Cliff, IsClosedOutwardDeterministicAndNearItsTarget) {
  const gi::Mesh m = cliff(20000);
  EXPECT_NEAR(double(m.triangle_count()), 20000.0, 0.05 * 20000);
  // Closed and consistently wound: every directed edge once, its reverse once.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t < m.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) ++directed[{m.indices[t + k], m.indices[t + (k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    ASSERT_EQ(n, 1);
    ASSERT_EQ(directed.count({e.second, e.first}), 1u);
  }
  // Outward: positive signed volume.
  double volume = 0.0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3)
    volume += glm::dot(glm::dvec3(m.positions[m.indices[t]]),
                       glm::cross(glm::dvec3(m.positions[m.indices[t + 1]]), glm::dvec3(m.positions[m.indices[t + 2]]))) / 6.0;
  EXPECT_GT(volume, 0.0);
  const gi::Mesh again = cliff(20000);
  EXPECT_EQ(again.positions, m.positions);
  EXPECT_EQ(again.indices, m.indices);
}

// The properties a LOD cut relies on. 100k triangles: the smallest cliff on
// which strict METIS balance (UFactor 1) already stalled the DAG (16 levels for
// an ideal 11, cluster_dag.h), and still well under a second to build.
TEST(ClusterDag, HalvesEachLevelWithMonotonicErrorsAndBounds) {
  const gi::Mesh m = cliff(100000);
  const gi::ClusterDag dag = gi::build_cluster_dag(m);
  RecordProperty("levels", int(dag.levels));
  RecordProperty("clusters", int(dag.clusters.size()));
  ASSERT_GT(dag.lod0_clusters, 700u);
  EXPECT_LE(std::abs(int(dag.levels) - int(dag.ideal_levels())), 1) << dag.to_json().dump();
  EXPECT_LE(dag.stuck_clusters(), dag.clusters.size() / 100) << dag.to_json().dump();
  std::uint64_t lod0_triangles = 0;
  for (std::uint32_t c = 0; c < dag.clusters.size(); ++c) {
    const gi::DagCluster& x = dag.clusters[c];
    ASSERT_LE(x.triangle_count, 128u);
    ASSERT_GT(x.triangle_count, 0u);
    if (c < dag.lod0_clusters) {
      ASSERT_EQ(x.level, 0u);
      ASSERT_EQ(x.error, 0.0f);
      lod0_triangles += x.triangle_count;
    }
    if (x.parent_group < 0) continue;
    const gi::DagGroup& g = dag.groups[x.parent_group];
    EXPECT_GE(g.error, x.error) << "cluster " << c;
    EXPECT_LE(glm::length(g.lod_bounds.center - x.lod_bounds.center) + x.lod_bounds.radius,
              g.lod_bounds.radius * (1.0f + 1e-5f))
        << "cluster " << c;
    for (std::uint32_t child : g.clusters) {  // what the group produced carries its sphere and error
      EXPECT_EQ(dag.clusters[child].error, g.error);
      EXPECT_GT(dag.clusters[child].level, x.level);
    }
  }
  EXPECT_EQ(lod0_triangles, m.triangle_count());
  const std::vector<gi::ClusterLevelStats> levels = dag.level_stats();
  EXPECT_EQ(levels.back().clusters, 1u) << "simplifies to one root";
  for (std::size_t l = 1; l < levels.size(); ++l) {
    EXPECT_LT(levels[l].triangles, levels[l - 1].triangles + 1);
    // What stalls a DAG: borders locked at one level left on the next level's
    // group borders until groups are nearly all border (0.95 under UFactor 1).
    EXPECT_LT(levels[l].locked, 0.6) << "level " << l << ": " << dag.to_json().dump();
  }
}

// Same bits on every run and at any thread count (groups simplify in parallel).
TEST(ClusterDag, IsDeterministic) {
  const gi::Mesh m = cliff(20000);
  const gi::ClusterDag a = gi::build_cluster_dag(m);
  gi::ClusterDag b;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    b = gi::build_cluster_dag(m);
  }
  EXPECT_EQ(a.content_hash(), b.content_hash());
  EXPECT_EQ(a.content_hash(), gi::build_cluster_dag(m).content_hash());
  EXPECT_EQ(a.indices, b.indices);
  ASSERT_EQ(a.clusters.size(), b.clusters.size());
  for (std::size_t i = 0; i < a.clusters.size(); ++i) {
    const gi::DagCluster &x = a.clusters[i], &y = b.clusters[i];
    EXPECT_TRUE(x.first_index == y.first_index && x.triangle_count == y.triangle_count && x.level == y.level &&
                x.group == y.group && x.parent_group == y.parent_group && x.error == y.error &&
                x.bounds.center == y.bounds.center && x.bounds.radius == y.bounds.radius &&
                x.lod_bounds.center == y.lod_bounds.center && x.lod_bounds.radius == y.lod_bounds.radius)
        << "cluster " << i;
  }
  ASSERT_EQ(a.groups.size(), b.groups.size());
  for (std::size_t i = 0; i < a.groups.size(); ++i) {
    EXPECT_EQ(a.groups[i].children, b.groups[i].children);
    EXPECT_EQ(a.groups[i].error, b.groups[i].error);
  }
}

// Fewer clusters than one group: METIS is skipped (k-way crashes on nparts = 1).
TEST(ClusterDag, TinyMeshesAndBadOptions) {
  const gi::ClusterDag tiny = gi::build_cluster_dag(cliff(400));
  EXPECT_LE(tiny.lod0_clusters, 8u);
  EXPECT_GE(tiny.levels, 1u);
  gi::ClusterDagOptions o;
  o.max_triangles = 126;  // meshoptimizer 0.18 wants a multiple of 4
  EXPECT_THROW(gi::build_cluster_dag(cliff(400), o), std::invalid_argument);
  o.max_triangles = 128;
  o.max_vertices = 256;
  EXPECT_THROW(gi::build_cluster_dag(cliff(400), o), std::invalid_argument);
  EXPECT_EQ(gi::build_cluster_dag(gi::Mesh{}).clusters.size(), 0u);
}

}  // namespace
