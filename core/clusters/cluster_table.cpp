#include "core/clusters/cluster_table.h"

#include <algorithm>
#include <array>
#include <map>
#include <stdexcept>

#include <fmt/format.h>
#include <meshoptimizer.h>

#include "core/clusters/cluster_ids.h"

namespace gi {
namespace {

using Key = std::array<std::uint32_t, 3>;

Key triangle_key(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  Key k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

}  // namespace

MeshClusterIds lod0_cluster_ids(const FlatGeometry& g, std::uint32_t mesh, std::uint32_t max_triangles) {
  const MeshRange& r = g.meshes.at(mesh);
  MeshClusterIds out;
  if (r.triangle_count == 0) return out;
  std::vector<float> positions(std::size_t(r.vertex_count) * 3);
  for (std::uint32_t v = 0; v < r.vertex_count; ++v)
    for (int k = 0; k < 3; ++k) positions[3 * v + k] = g.vertices[r.first_vertex + v].position[k];
  const std::uint32_t* indices = g.indices.data() + r.first_index;
  const std::size_t index_count = std::size_t(r.triangle_count) * 3;
  const std::size_t max_vertices = 255;
  const std::size_t bound = meshopt_buildMeshletsBound(index_count, max_vertices, max_triangles);
  std::vector<meshopt_Meshlet> meshlets(bound);
  std::vector<unsigned int> mv(bound * max_vertices);
  std::vector<unsigned char> mt(bound * max_triangles * 3);
  const std::size_t n = meshopt_buildMeshlets(meshlets.data(), mv.data(), mt.data(), indices, index_count,
                                              positions.data(), r.vertex_count, 3 * sizeof(float), max_vertices,
                                              max_triangles, 0.0f);
  // meshoptimizer returns vertices, not triangle ids: find each triangle again.
  std::map<Key, std::vector<std::uint32_t>> by_key;
  for (std::uint32_t t = 0; t < r.triangle_count; ++t)
    by_key[triangle_key(indices[3 * t], indices[3 * t + 1], indices[3 * t + 2])].push_back(t);
  for (auto& [k, v] : by_key) std::reverse(v.begin(), v.end());  // pop_back takes them in order
  for (std::size_t m = 0; m < n; ++m) {
    std::vector<std::uint32_t> prims;
    for (std::uint32_t t = 0; t < meshlets[m].triangle_count; ++t) {
      const unsigned char* tri = &mt[meshlets[m].triangle_offset + 3 * t];
      const unsigned int* vtx = &mv[meshlets[m].vertex_offset];
      std::vector<std::uint32_t>& list = by_key.at(triangle_key(vtx[tri[0]], vtx[tri[1]], vtx[tri[2]]));
      prims.push_back(list.back());
      list.pop_back();
    }
    out.lod0_primitives.push_back(std::move(prims));
  }
  out.id_count = static_cast<std::uint32_t>(out.lod0_primitives.size());
  return out;
}

MeshClusterIds dag_cluster_ids(const ClusterDag& dag, const FlatGeometry& g, std::uint32_t mesh) {
  const MeshRange& r = g.meshes.at(mesh);
  const std::uint32_t* indices = g.indices.data() + r.first_index;
  std::map<Key, std::vector<std::uint32_t>> by_key;
  for (std::uint32_t t = 0; t < r.triangle_count; ++t)
    by_key[triangle_key(indices[3 * t], indices[3 * t + 1], indices[3 * t + 2])].push_back(t);
  for (auto& [k, v] : by_key) std::reverse(v.begin(), v.end());
  MeshClusterIds out;
  out.id_count = static_cast<std::uint32_t>(dag.clusters.size());
  for (std::uint32_t c = 0; c < dag.lod0_clusters; ++c) {
    const DagCluster& cl = dag.clusters[c];
    std::vector<std::uint32_t> prims;
    for (std::uint32_t t = 0; t < cl.triangle_count; ++t) {
      const std::uint32_t* tri = &dag.indices[cl.first_index + 3 * t];
      auto it = by_key.find(triangle_key(tri[0], tri[1], tri[2]));
      if (it == by_key.end() || it->second.empty())
        throw std::invalid_argument(fmt::format("dag_cluster_ids: mesh {} has no triangle {} {} {} (DAG of another mesh?)",
                                                mesh, tri[0], tri[1], tri[2]));
      prims.push_back(it->second.back());
      it->second.pop_back();
    }
    out.lod0_primitives.push_back(std::move(prims));
  }
  return out;
}

std::vector<std::uint32_t> build_cluster_table(const std::vector<MeshRange>& ranges, std::size_t triangles,
                                               const std::vector<MeshClusterIds>& meshes,
                                               const std::vector<shader::GpuInstance>& instances,
                                               const std::vector<bool>& visible, const ClusterIdLayout& layout) {
  using namespace shader;
  if (meshes.size() != ranges.size())
    throw std::invalid_argument(fmt::format("build_cluster_table: {} meshes, {} cluster lists", ranges.size(), meshes.size()));
  if (layout.triangle_bits < 2 || layout.triangle_bits > 8 || layout.cluster_bits == 0 ||
      layout.cluster_bits + layout.triangle_bits > 32)
    throw std::invalid_argument(fmt::format("cluster/triangle bits {}/{}: need triangle bits in 2..8 and a sum ≤ 32",
                                            layout.cluster_bits, layout.triangle_bits));
  const std::uint32_t max_triangles = 1u << layout.triangle_bits;
  std::vector<std::uint32_t> first_cluster(meshes.size() + 1, 0);
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    for (const auto& c : meshes[m].lod0_primitives)
      if (c.size() > max_triangles)
        throw std::invalid_argument(fmt::format("mesh {} has a cluster of {} triangles; {} triangle bits name {}", m,
                                                c.size(), layout.triangle_bits, max_triangles));
    first_cluster[m + 1] = first_cluster[m] + static_cast<std::uint32_t>(meshes[m].lod0_primitives.size());
  }
  std::vector<std::uint32_t> t(CT_HEADER_WORDS, 0);
  t[CT_CLUSTER_BITS] = layout.cluster_bits;
  t[CT_TRIANGLE_BITS] = layout.triangle_bits;
  t[CT_INSTANCE_COUNT] = static_cast<std::uint32_t>(instances.size());
  t[CT_INSTANCES] = CT_HEADER_WORDS;
  t[CT_PRIMITIVES] = t[CT_INSTANCES] + 4 * static_cast<std::uint32_t>(instances.size());
  t[CT_CLUSTERS] = t[CT_PRIMITIVES] + static_cast<std::uint32_t>(triangles);
  t[CT_MAX_TRIANGLES] = max_triangles;
  t.resize(std::size_t(t[CT_CLUSTERS]) + std::size_t(first_cluster.back()) * max_triangles, CLUSTER_NO_PRIMITIVE);

  std::uint32_t next_id = 0;  // 32-bit like the GPU: tables are for drawn scenes, far below 2^32 IDs
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const std::uint32_t first_index = instances[i].first_index;
    const auto m = std::find_if(ranges.begin(), ranges.end(),
                                [&](const MeshRange& r) { return r.first_index == first_index; }) - ranges.begin();
    if (m == std::ptrdiff_t(ranges.size()))
      throw std::invalid_argument(fmt::format("build_cluster_table: instance {} starts at no mesh", i));
    const bool shown = i >= visible.size() || visible[i];
    std::uint32_t* rec = &t[t[CT_INSTANCES] + 4 * i];
    rec[0] = next_id;
    rec[1] = shown ? meshes[m].id_count : 0u;
    rec[2] = first_cluster[m];
    rec[3] = static_cast<std::uint32_t>(meshes[m].lod0_primitives.size());
    next_id += rec[1];
  }
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const std::uint32_t first_triangle = ranges[m].first_index / 3;
    for (std::size_t c = 0; c < meshes[m].lod0_primitives.size(); ++c) {
      const std::vector<std::uint32_t>& prims = meshes[m].lod0_primitives[c];
      for (std::size_t k = 0; k < prims.size(); ++k) {
        t[t[CT_PRIMITIVES] + first_triangle + prims[k]] = static_cast<std::uint32_t>(c << 8 | k);
        t[t[CT_CLUSTERS] + std::size_t(first_cluster[m] + c) * max_triangles + k] = prims[k];
      }
    }
  }
  return t;
}

std::uint64_t cluster_ids_in_use(const std::vector<std::uint32_t>& t) {
  using namespace shader;
  std::uint64_t n = 0;
  for (std::uint32_t i = 0; i < t[CT_INSTANCE_COUNT]; ++i) n += t[t[CT_INSTANCES] + 4 * i + 1];
  return n;
}

DecodedVisibility decode_packed_visibility(const std::vector<std::uint32_t>& t, std::uint32_t packed) {
  using namespace shader;
  DecodedVisibility d;
  const std::uint32_t id = cluster_unpack_id(packed, t[CT_CLUSTER_BITS], t[CT_TRIANGLE_BITS]);
  const std::uint32_t tri = cluster_unpack_triangle(packed, t[CT_TRIANGLE_BITS]);
  // The last instance whose first ID is ≤ id (hidden ones own none, so it is a shown one).
  std::uint32_t lo = 0, hi = t[CT_INSTANCE_COUNT];
  while (hi - lo > 1) {
    const std::uint32_t mid = (lo + hi) / 2;
    if (t[t[CT_INSTANCES] + 4 * mid] <= id) lo = mid; else hi = mid;
  }
  if (t[CT_INSTANCE_COUNT] == 0) return d;
  const std::uint32_t* rec = &t[t[CT_INSTANCES] + 4 * lo];
  const std::uint32_t local = id - rec[0];
  if (id < rec[0] || local >= rec[1] || local >= rec[3]) return d;  // not a drawn (LOD-0) cluster
  const std::uint32_t prim = t[t[CT_CLUSTERS] + std::size_t(rec[2] + local) * t[CT_MAX_TRIANGLES] + tri];
  if (prim == CLUSTER_NO_PRIMITIVE) return d;
  d.valid = true;
  d.instance = lo;
  d.primitive = prim;
  return d;
}

}  // namespace gi
