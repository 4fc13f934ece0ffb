#include "core/clusters/cluster_dag.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <meshoptimizer.h>
#include <metis.h>
#include <tbb/parallel_for.h>
#include <xxhash.h>

namespace gi {
namespace {

constexpr std::size_t kStride = sizeof(glm::vec3);
static_assert(sizeof(glm::vec3) == 3 * sizeof(float));

const float* floats(const std::vector<glm::vec3>& p) { return p.empty() ? nullptr : &p[0].x; }

// Meshlets of an index list over `positions` (the vertex space of `indices`),
// each returned as a plain triangle list in that vertex space.
std::vector<std::vector<std::uint32_t>> build_meshlets(const std::vector<std::uint32_t>& indices,
                                                       const std::vector<glm::vec3>& positions,
                                                       const ClusterDagOptions& o) {
  const std::size_t bound = meshopt_buildMeshletsBound(indices.size(), o.max_vertices, o.max_triangles);
  std::vector<meshopt_Meshlet> meshlets(bound);
  std::vector<unsigned int> vertices(bound * o.max_vertices);
  std::vector<unsigned char> triangles(bound * o.max_triangles * 3);
  const std::size_t n = meshopt_buildMeshlets(meshlets.data(), vertices.data(), triangles.data(), indices.data(),
                                              indices.size(), floats(positions), positions.size(), kStride,
                                              o.max_vertices, o.max_triangles, 0.0f);
  std::vector<std::vector<std::uint32_t>> out(n);
  for (std::size_t m = 0; m < n; ++m) {
    const meshopt_Meshlet& ml = meshlets[m];
    out[m].reserve(ml.triangle_count * 3);
    for (std::size_t k = 0; k < ml.triangle_count * 3; ++k)
      out[m].push_back(vertices[ml.vertex_offset + triangles[ml.triangle_offset + k]]);
  }
  return out;
}

Sphere cluster_bounds(const std::uint32_t* indices, std::size_t count, const std::vector<glm::vec3>& positions) {
  const meshopt_Bounds b = meshopt_computeClusterBounds(indices, count, floats(positions), positions.size(), kStride);
  return Sphere{glm::vec3(b.center[0], b.center[1], b.center[2]), b.radius};
}

// Groups of the clusters in `queue` by shared edges (edge keys over
// position-welded vertex ids), as lists of positions in `queue`.
std::vector<std::vector<std::uint32_t>> group_clusters(const ClusterDag& dag, const std::vector<std::uint32_t>& queue,
                                                       const std::vector<std::uint32_t>& weld,
                                                       const ClusterDagOptions& o) {
  const std::uint32_t n = static_cast<std::uint32_t>(queue.size());
  const std::uint32_t parts = (n + o.group_size - 1) / o.group_size;
  std::vector<std::vector<std::uint32_t>> groups;
  if (parts <= 1) {  // METIS k-way crashes on nparts = 1
    groups.emplace_back(n);
    for (std::uint32_t i = 0; i < n; ++i) groups[0][i] = i;
    return groups;
  }
  // (edge, cluster) for every triangle edge; equal edges are adjacent after sorting.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;
  for (std::uint32_t q = 0; q < n; ++q) {
    const DagCluster& c = dag.clusters[queue[q]];
    for (std::uint32_t t = 0; t < c.triangle_count; ++t)
      for (int k = 0; k < 3; ++k) {
        std::uint64_t a = weld[dag.indices[c.first_index + 3 * t + k]];
        std::uint64_t b = weld[dag.indices[c.first_index + 3 * t + (k + 1) % 3]];
        if (a == b) continue;
        edges.emplace_back(std::min(a, b) << 32 | std::max(a, b), q);
      }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> links;  // (a, b) with a != b, once per shared edge
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (std::size_t x = i; x < j; ++x)
      for (std::size_t y = x + 1; y < j; ++y)
        if (edges[x].second != edges[y].second) {
          links.emplace_back(edges[x].second, edges[y].second);
          links.emplace_back(edges[y].second, edges[x].second);
        }
    i = j;
  }
  std::sort(links.begin(), links.end());
  std::vector<idx_t> xadj(n + 1, 0), adjncy, adjwgt;
  for (std::size_t i = 0; i < links.size();) {
    std::size_t j = i;
    while (j < links.size() && links[j] == links[i]) ++j;
    adjncy.push_back(static_cast<idx_t>(links[i].second));
    adjwgt.push_back(static_cast<idx_t>(j - i));  // shared edge count
    ++xadj[links[i].first + 1];
    i = j;
  }
  for (std::uint32_t v = 0; v < n; ++v) xadj[v + 1] += xadj[v];

  std::vector<idx_t> part(n, 0);
  if (adjncy.empty()) {
    for (std::uint32_t v = 0; v < n; ++v) part[v] = static_cast<idx_t>(v / o.group_size);
  } else {
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_UFACTOR] = static_cast<idx_t>(o.group_ufactor);  // not 1: cluster_dag.h says why
    options[METIS_OPTION_SEED] = 42;     // deterministic (Bevy 0.15)
    options[METIS_OPTION_NUMBERING] = 0;
    idx_t nv = static_cast<idx_t>(n), ncon = 1, np = static_cast<idx_t>(parts), cut = 0;
    const int status = METIS_PartGraphKway(&nv, &ncon, xadj.data(), adjncy.data(), nullptr, nullptr, adjwgt.data(),
                                           &np, nullptr, nullptr, options, &cut, part.data());
    if (status != METIS_OK) throw std::runtime_error(fmt::format("METIS_PartGraphKway failed ({})", status));
  }
  std::vector<std::vector<std::uint32_t>> by_part(parts);
  for (std::uint32_t v = 0; v < n; ++v) by_part[static_cast<std::size_t>(part[v])].push_back(v);
  for (auto& g : by_part)
    if (!g.empty()) groups.push_back(std::move(g));  // small graphs can leave parts empty
  return groups;
}

// One group's simplification: new clusters (global vertex ids) or nothing if stuck.
struct GroupResult {
  bool simplified = false;
  std::vector<std::vector<std::uint32_t>> clusters;
  std::vector<Sphere> bounds;
  float error = 0.0f;  // this simplification's object-space error
  std::uint32_t vertices = 0, locked_vertices = 0;
};

// Distinct vertices of a triangle list and how many lie on its topological
// border (an edge used once): what meshopt_SimplifyLockBorder locks. Counted on
// position-welded ids, as meshoptimizer treats attribute seams as interior.
std::pair<std::uint32_t, std::uint32_t> vertex_and_border_counts(const std::vector<std::uint32_t>& welded) {
  std::vector<std::uint64_t> edges;
  edges.reserve(welded.size());
  for (std::size_t t = 0; t < welded.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = welded[t + k], b = welded[t + (k + 1) % 3];
      if (a != b) edges.push_back(std::min(a, b) << 32 | std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::uint32_t> border;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) {
      border.push_back(static_cast<std::uint32_t>(edges[i] >> 32));
      border.push_back(static_cast<std::uint32_t>(edges[i] & 0xFFFFFFFFu));
    }
    i = j;
  }
  std::vector<std::uint32_t> all = welded;
  for (std::vector<std::uint32_t>* v : {&all, &border}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  return {static_cast<std::uint32_t>(all.size()), static_cast<std::uint32_t>(border.size())};
}

GroupResult simplify_group(const ClusterDag& dag, const std::vector<std::uint32_t>& members, const Mesh& mesh,
                           const std::vector<std::uint32_t>& weld, const ClusterDagOptions& o) {
  std::vector<std::uint32_t> merged;
  for (std::uint32_t c : members) {
    const DagCluster& cl = dag.clusters[c];
    merged.insert(merged.end(), dag.indices.begin() + cl.first_index,
                  dag.indices.begin() + cl.first_index + 3 * cl.triangle_count);
  }
  // Compact: meshopt_simplify allocates for its whole vertex count.
  std::vector<std::uint32_t> used = merged;
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<glm::vec3> local_positions(used.size());
  for (std::size_t i = 0; i < used.size(); ++i) local_positions[i] = mesh.positions[used[i]];
  std::vector<std::uint32_t> local(merged.size());
  for (std::size_t i = 0; i < merged.size(); ++i)
    local[i] = static_cast<std::uint32_t>(std::lower_bound(used.begin(), used.end(), merged[i]) - used.begin());

  const std::size_t target = (merged.size() / 3 / 2) * 3;
  std::vector<std::uint32_t> simplified(local.size());
  float relative_error = 0.0f;
  const std::size_t count =
      meshopt_simplify(simplified.data(), local.data(), local.size(), floats(local_positions), local_positions.size(),
                       kStride, target, 1.0f, meshopt_SimplifyLockBorder, &relative_error);
  GroupResult r;
  std::vector<std::uint32_t> welded(merged.size());
  for (std::size_t i = 0; i < merged.size(); ++i) welded[i] = weld[merged[i]];
  std::tie(r.vertices, r.locked_vertices) = vertex_and_border_counts(welded);
  if (count == 0 || static_cast<float>(count) > o.max_simplified_ratio * static_cast<float>(merged.size())) return r;
  simplified.resize(count);
  r.simplified = true;
  r.error = relative_error * meshopt_simplifyScale(floats(local_positions), local_positions.size(), kStride);
  for (std::vector<std::uint32_t>& c : build_meshlets(simplified, local_positions, o)) {
    r.bounds.push_back(cluster_bounds(c.data(), c.size(), local_positions));
    for (std::uint32_t& v : c) v = used[v];
    r.clusters.push_back(std::move(c));
  }
  return r;
}

std::uint32_t append_cluster(ClusterDag& dag, const std::vector<std::uint32_t>& tri, std::uint32_t level,
                             std::int32_t group, const Sphere& bounds, const Sphere& lod_bounds, float error) {
  DagCluster c;
  c.first_index = static_cast<std::uint32_t>(dag.indices.size());
  c.triangle_count = static_cast<std::uint32_t>(tri.size() / 3);
  c.level = level;
  c.group = group;
  c.bounds = bounds;
  c.lod_bounds = lod_bounds;
  c.error = error;
  dag.indices.insert(dag.indices.end(), tri.begin(), tri.end());
  dag.clusters.push_back(c);
  return static_cast<std::uint32_t>(dag.clusters.size() - 1);
}

}  // namespace

Sphere enclose(const Sphere& a, const Sphere& b) {
  const float d = glm::length(b.center - a.center);
  if (d + b.radius <= a.radius) return a;
  if (d + a.radius <= b.radius) return b;
  Sphere s;
  s.radius = 0.5f * (d + a.radius + b.radius);
  s.center = a.center + (b.center - a.center) * ((s.radius - a.radius) / d);
  // Rounding must never leave a child poking out (monotonic bounds).
  s.radius *= 1.0f + 4.0f * std::numeric_limits<float>::epsilon();
  return s;
}

ClusterDag build_cluster_dag(const Mesh& mesh, const ClusterDagOptions& o) {
  if (o.max_triangles == 0 || o.max_triangles % 4 != 0 || o.max_triangles > 512)
    throw std::invalid_argument(fmt::format("max_triangles must be a multiple of 4 in 4..512, got {}", o.max_triangles));
  if (o.max_vertices < 3 || o.max_vertices > 255)
    throw std::invalid_argument(fmt::format("max_vertices must be in 3..255, got {}", o.max_vertices));
  if (o.group_size < 2) throw std::invalid_argument("group_size must be at least 2");
  const auto start = std::chrono::steady_clock::now();
  ClusterDag dag;
  dag.options = o;
  if (mesh.indices.empty()) return dag;

  // Vertex ids welded by position: groups follow geometry, not attribute seams.
  std::vector<std::uint32_t> weld(mesh.positions.size());
  meshopt_generateVertexRemap(weld.data(), nullptr, mesh.positions.size(), floats(mesh.positions),
                              mesh.positions.size(), kStride);

  std::vector<std::uint32_t> queue;
  for (const std::vector<std::uint32_t>& c : build_meshlets(mesh.indices, mesh.positions, o)) {
    const Sphere b = cluster_bounds(c.data(), c.size(), mesh.positions);
    queue.push_back(append_cluster(dag, c, 0, -1, b, b, 0.0f));
  }
  dag.lod0_clusters = static_cast<std::uint32_t>(queue.size());

  for (std::uint32_t round = 0; queue.size() > 1 && round + 1 < o.max_levels; ++round) {
    const std::vector<std::vector<std::uint32_t>> parts = group_clusters(dag, queue, weld, o);
    std::vector<std::vector<std::uint32_t>> members(parts.size());
    for (std::size_t g = 0; g < parts.size(); ++g)
      for (std::uint32_t q : parts[g]) members[g].push_back(queue[q]);
    std::vector<GroupResult> results(parts.size());
    tbb::parallel_for(std::size_t(0), parts.size(),
                      [&](std::size_t g) { results[g] = simplify_group(dag, members[g], mesh, weld, o); });

    std::vector<std::uint32_t> next;
    bool any = false;
    for (std::size_t g = 0; g < parts.size(); ++g) {
      if (!results[g].simplified) {  // stuck: try again with the next level's clusters
        next.insert(next.end(), members[g].begin(), members[g].end());
        continue;
      }
      any = true;
      DagGroup group;
      group.level = round + 1;
      group.children = members[g];
      float child_error = 0.0f;
      group.lod_bounds = dag.clusters[members[g][0]].lod_bounds;
      for (std::uint32_t c : members[g]) {
        child_error = std::max(child_error, dag.clusters[c].error);
        group.lod_bounds = enclose(group.lod_bounds, dag.clusters[c].lod_bounds);
      }
      group.error = child_error + results[g].error;
      group.vertices = results[g].vertices;
      group.locked_vertices = results[g].locked_vertices;
      const std::int32_t gi = static_cast<std::int32_t>(dag.groups.size());
      for (std::uint32_t c : members[g]) dag.clusters[c].parent_group = gi;
      for (std::size_t k = 0; k < results[g].clusters.size(); ++k) {
        const std::uint32_t id = append_cluster(dag, results[g].clusters[k], round + 1, gi, results[g].bounds[k],
                                                group.lod_bounds, group.error);
        group.clusters.push_back(id);
        next.push_back(id);
      }
      dag.groups.push_back(std::move(group));
    }
    if (!any) break;  // nothing simplifies any more
    queue = std::move(next);
  }
  for (const DagCluster& c : dag.clusters) dag.levels = std::max(dag.levels, c.level + 1);
  dag.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return dag;
}

std::uint32_t ClusterDag::ideal_levels() const {
  if (lod0_clusters == 0) return 0;
  return static_cast<std::uint32_t>(std::ceil(std::log2(static_cast<double>(lod0_clusters)))) + 1;
}

std::vector<ClusterLevelStats> ClusterDag::level_stats() const {
  std::vector<ClusterLevelStats> s(levels);
  for (std::uint32_t l = 0; l < levels; ++l) s[l].level = l;
  for (const DagCluster& c : clusters) {
    ClusterLevelStats& x = s[c.level];
    ++x.clusters;
    x.triangles += c.triangle_count;
    if (c.parent_group < 0 && c.level + 1 < levels) ++x.stuck;
  }
  std::vector<std::uint64_t> vertices(levels, 0), locked(levels, 0);
  for (const DagGroup& g : groups) {
    vertices[g.level] += g.vertices;
    locked[g.level] += g.locked_vertices;
  }
  for (std::uint32_t l = 0; l < levels; ++l)
    s[l].locked = vertices[l] ? double(locked[l]) / double(vertices[l]) : 0.0;
  for (ClusterLevelStats& x : s)
    x.fill = x.clusters ? static_cast<double>(x.triangles) / (double(x.clusters) * options.max_triangles) : 0.0;
  return s;
}

std::uint32_t ClusterDag::stuck_clusters() const {
  std::uint32_t n = 0;
  for (const ClusterLevelStats& x : level_stats()) n += x.stuck;
  return n;
}

std::uint64_t ClusterDag::content_hash() const {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  auto add = [&](const void* p, std::size_t n) { XXH3_64bits_update(state, p, n); };
  add(indices.data(), indices.size() * sizeof(std::uint32_t));
  for (const DagCluster& c : clusters) {  // field by field: no padding bytes hashed
    for (std::uint32_t v : {c.first_index, c.triangle_count, c.level}) add(&v, sizeof v);
    for (std::int32_t v : {c.group, c.parent_group}) add(&v, sizeof v);
    for (const Sphere* sp : {&c.bounds, &c.lod_bounds}) {
      add(&sp->center.x, 3 * sizeof(float));
      add(&sp->radius, sizeof(float));
    }
    add(&c.error, sizeof c.error);
  }
  for (const DagGroup& g : groups) {
    add(g.children.data(), g.children.size() * sizeof(std::uint32_t));
    add(&g.error, sizeof g.error);
  }
  const std::uint64_t h = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return h;
}

nlohmann::json ClusterDag::to_json() const {
  nlohmann::json levels_json = nlohmann::json::array();
  for (const ClusterLevelStats& x : level_stats())
    levels_json.push_back({{"level", x.level},
                           {"clusters", x.clusters},
                           {"triangles", x.triangles},
                           {"fill", x.fill},
                           {"locked", x.locked},
                           {"stuck", x.stuck}});
  const std::uint32_t stuck = stuck_clusters();
  return {{"lod0_clusters", lod0_clusters},
          {"clusters", clusters.size()},
          {"groups", groups.size()},
          {"levels", levels},
          {"ideal_levels", ideal_levels()},
          {"stuck", stuck},
          {"stuck_fraction", clusters.empty() ? 0.0 : double(stuck) / double(clusters.size())},
          {"max_triangles", options.max_triangles},
          {"group_ufactor", options.group_ufactor},
          {"hash", fmt::format("{:016x}", content_hash())},
          {"build_seconds", build_seconds},
          {"per_level", levels_json}};
}

}  // namespace gi
