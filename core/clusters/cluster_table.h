// Host side of the packed visibility IDs (core/clusters/cluster_ids.h): which
// primitives form each LOD-0 cluster of each flattened mesh, how many IDs each
// instance owns, the table the GPU passes read, and the CPU decode that mirrors
// gpu/shaders/gbuffer_resolve.comp (used by the cluster_ids check and tests).
#pragma once
#include <cstdint>
#include <vector>

#include "core/clusters/cluster_dag.h"
#include "core/scene_flatten.h"

namespace gi {

struct ClusterIdLayout {
  std::uint32_t cluster_bits = 25;
  std::uint32_t triangle_bits = 7;
  std::uint64_t id_limit() const { return std::uint64_t(1) << cluster_bits; }  // IDs 0 .. limit-1 fit
};

// One mesh's clusters as the ID space sees them.
struct MeshClusterIds {
  std::uint32_t id_count = 0;  // IDs per instance: every cluster of its DAG
  std::vector<std::vector<std::uint32_t>> lod0_primitives;  // per LOD-0 cluster: mesh-local primitives (flattened order)
};

// LOD-0 meshlets of flattened mesh `mesh` only (no DAG): IDs = LOD-0 clusters.
// What the renderer uses when nobody hands it DAGs.
MeshClusterIds lod0_cluster_ids(const FlatGeometry& geometry, std::uint32_t mesh, std::uint32_t max_triangles);
// A DAG built on the scene's mesh `mesh`, its LOD-0 clusters mapped to the
// flattened (Morton-sorted) primitive order; id_count = all its clusters.
MeshClusterIds dag_cluster_ids(const ClusterDag& dag, const FlatGeometry& geometry, std::uint32_t mesh);

// The table of cluster_ids.h. meshes/triangle_count: FlatGeometry::meshes and
// indices.size() / 3; instances/visible as Renderer::update_scene gets them;
// hidden instances own no IDs. Throws std::invalid_argument for bits outside
// triangle 2..8 / sum ≤ 32, or a cluster larger than triangle_bits can name.
std::vector<std::uint32_t> build_cluster_table(const std::vector<MeshRange>& mesh_ranges, std::size_t triangle_count,
                                               const std::vector<MeshClusterIds>& meshes,
                                               const std::vector<shader::GpuInstance>& instances,
                                               const std::vector<bool>& visible, const ClusterIdLayout& layout);
// IDs the visible instances own (what must fit in cluster_bits).
std::uint64_t cluster_ids_in_use(const std::vector<std::uint32_t>& table);

struct DecodedVisibility {
  bool valid = false;  // the ID names a drawn (LOD-0) triangle of some instance
  std::uint32_t instance = 0;
  std::uint32_t primitive = 0;
};
// What gbuffer_resolve.comp decodes from a packed ID.
DecodedVisibility decode_packed_visibility(const std::vector<std::uint32_t>& table, std::uint32_t packed);

}  // namespace gi
