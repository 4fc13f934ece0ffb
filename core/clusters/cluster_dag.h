// A Nanite-style cluster DAG for one mesh (docs/design.md §8), built the way Bevy's
// virtual geometry builds it (seeds/virtual-geometry-0.14..0.16):
//
//   level 0: meshlets of ≤ max_triangles triangles (meshopt_buildMeshlets);
//   repeat:  group the current clusters by shared edges (METIS k-way, about
//            group_size clusters per group), merge each group's triangles,
//            simplify them to about half with the group border locked, split the
//            result into new meshlets (the next level);
//   until one cluster is left or nothing simplifies any more.
//
// Clusters a group failed to halve ("stuck") go back into the queue and are
// tried again at the next level, as Bevy 0.15 does. Errors are cumulative from
// level 0 (max of the children + this simplification's object-space error), and
// each group's LOD sphere encloses its children's, so both grow monotonically
// up the DAG — what a LOD cut relies on.
//
// Why the grouping is not held to UFactor 1 (docs/design.md §8 says 1; README "Design
// notes"): every group border is locked, so the next level only halves if most
// of the last level's (dense, locked) borders end up inside the new groups.
// Forcing exactly group_size clusters per group leaves METIS no room to cut
// along the sparse interior seams instead: on a 1 M-triangle cliff the share of
// locked vertices in the groups that simplified climbed 0.31, 0.51, 0.68, 0.86
// over levels 1-4, most groups stopped halving and the DAG took 41 levels (ideal
// 14, 1.55 % stuck). With 20 % imbalance allowed (group_ufactor = 200) it stays
// within 0.22-0.37 and the DAG is ideal, 0 stuck, up to 4 M triangles
// (ClusterLevelStats::locked shows it per level). UFactor 1 is right where Bevy
// 0.16 used it, for triangle clustering, where a part must fit a meshlet.
//
// meshoptimizer 0.18 / METIS 5.1.0 (Debian bookworm) shape the code:
// max_triangles must be a multiple of 4 and max_vertices ≤ 255; meshopt_simplify
// has only LockBorder (the topological border of the submesh it is given: the
// group border plus any open border of the mesh itself, so open meshes keep
// their outline — closed meshes such as the procedural cliff simplify to one
// cluster) and allocates for its whole vertex count, so each group is compacted
// first; METIS k-way with nparts = 1 crashes, so one group skips METIS, and
// empty parts are dropped.
//
// Deterministic: METIS gets a fixed seed, groups are simplified in parallel but
// collected in group order, so the same mesh gives the same DAG at any thread count.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/scene.h"

namespace gi {

struct ClusterDagOptions {
  std::uint32_t max_triangles = 128;  // multiple of 4, ≤ 512 (meshopt_computeClusterBounds)
  std::uint32_t max_vertices = 255;   // ≤ 255 (meshoptimizer 0.18)
  std::uint32_t group_size = 8;       // clusters per METIS group (Bevy 0.15: 8)
  // METIS UFactor for grouping, in 1/1000: groups may hold up to 20 % more than
  // the mean. 1 (strict balance) makes large meshes stall; see the top comment.
  std::uint32_t group_ufactor = 200;
  // A group whose simplified triangle count exceeds this fraction of its input
  // did not simplify: its clusters are stuck for this round.
  float max_simplified_ratio = 0.85f;
  std::uint32_t max_levels = 64;      // a guard, never reached by a sane mesh
};

struct Sphere {
  glm::vec3 center{0.0f};
  float radius = 0.0f;
};

struct DagCluster {
  std::uint32_t first_index = 0;     // into ClusterDag::indices
  std::uint32_t triangle_count = 0;
  std::uint32_t level = 0;
  std::int32_t group = -1;           // the group it was simplified from (-1 at level 0)
  std::int32_t parent_group = -1;    // the group it was simplified into (-1: a root or stuck)
  Sphere bounds;                     // culling sphere (meshopt_computeClusterBounds)
  Sphere lod_bounds;                 // level 0: its bounds; above: its group's LOD sphere
  float error = 0.0f;                // object-space error relative to level 0 (0 at level 0)
};

struct DagGroup {
  std::uint32_t level = 0;                 // level of the clusters it produced
  std::vector<std::uint32_t> children;     // clusters simplified into it
  std::vector<std::uint32_t> clusters;     // clusters it produced
  Sphere lod_bounds;                       // encloses every child's lod_bounds
  float error = 0.0f;                      // max child error + simplification error
  std::uint32_t vertices = 0;              // distinct vertices of the merged children
  std::uint32_t locked_vertices = 0;       // of them on the group's border (locked while simplifying)
};

struct ClusterLevelStats {
  std::uint32_t level = 0;
  std::uint32_t clusters = 0;
  std::uint64_t triangles = 0;
  double fill = 0.0;          // mean triangles per cluster / max_triangles
  std::uint32_t stuck = 0;    // clusters of this level that never got a parent (top level excluded)
  // Share of the vertices locked on group borders when the groups that made
  // this level were simplified (0 at level 0): when it nears 1, groups cannot halve.
  double locked = 0.0;
};

struct ClusterDag {
  ClusterDagOptions options;
  std::vector<std::uint32_t> indices;  // every cluster's triangles, indices into the mesh's positions
  std::vector<DagCluster> clusters;    // level 0 first (0 .. lod0_clusters-1), then by level
  std::vector<DagGroup> groups;
  std::uint32_t lod0_clusters = 0;
  std::uint32_t levels = 0;            // 1 + highest level
  double build_seconds = 0.0;

  std::uint32_t ideal_levels() const;  // ceil(log2(lod0_clusters)) + 1
  std::uint32_t stuck_clusters() const;
  std::vector<ClusterLevelStats> level_stats() const;
  // XXH3 of every cluster's triangles, level, links, bounds and error and every
  // group's children: equal hashes mean the same DAG bits (determinism checks).
  std::uint64_t content_hash() const;
  nlohmann::json to_json() const;      // levels, per-level table, totals, hash
};

// Throws std::invalid_argument for options outside meshoptimizer 0.18's limits.
ClusterDag build_cluster_dag(const Mesh& mesh, const ClusterDagOptions& options = {});

// The smallest sphere of the simple kind that encloses both (exact for two spheres).
Sphere enclose(const Sphere& a, const Sphere& b);

}  // namespace gi
