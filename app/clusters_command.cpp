// giharness clusters MESH_OR_SCENARIO [--json] (docs/design.md §8, §11): builds the
// cluster DAG of every mesh and prints its per-level table (clusters,
// triangles, fill, stuck, locked), the levels against the ideal ceil(log2(lod0)) + 1,
// the build time and the process's peak memory.
//
// MESH_OR_SCENARIO: a scenario file (*.json: every mesh of its scene after its
// last frame's events, spawned meshes included), a glTF file (*.gltf, *.glb),
// or a mesh generator with params: "cliff" or "cliff:triangles=1000000,seed=2".
#include <cstdio>
#include <sys/resource.h>

#include <fmt/format.h>

#include "core/clusters/cluster_dag.h"
#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "core/scenes/cliff.h"
#include "app/commands.h"
#include "core/scene_events.h"

namespace gi {
namespace {

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;  // Linux: KiB
}

// "cliff:triangles=1000000,seed=2" → the cliff's mesh.
Mesh generator_mesh(const std::string& spec) {
  const std::size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  if (name != "cliff")
    throw InputError(spec, "", "expected a scenario (.json), a glTF file (.gltf, .glb) or a mesh generator "
                               "(cliff[:key=value,...])");
  nlohmann::json params = nlohmann::json::object();
  if (colon != std::string::npos) {
    std::string rest = spec.substr(colon + 1);
    std::size_t start = 0;
    while (start < rest.size()) {
      std::size_t end = rest.find(',', start);
      if (end == std::string::npos) end = rest.size();
      const std::string item = rest.substr(start, end - start);
      const std::size_t eq = item.find('=');
      if (eq == std::string::npos) throw InputError(spec, "", "expected key=value, got \"" + item + "\"");
      const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
      try {
        params[key] = nlohmann::json::parse(value);
      } catch (const nlohmann::json::parse_error&) {
        throw InputError(spec, "/" + key, "expected a number, got \"" + value + "\"");
      }
      start = end + 1;
    }
  }
  // The scenario machinery validates the params exactly as a spawn would.
  Scenario s = parse_scenario({{"name", "clusters"}, {"scene", {{"generator", "cornell_box"}}},
                               {"resolution", {1, 1}}, {"frames", 1}},
                              spec);
  return generate_mesh(MeshGeneratorSpec{"cliff", params}, s, "").mesh;
}

std::vector<Mesh> meshes_of(const std::filesystem::path& input) {
  const std::string ext = input.extension().string();
  if (ext == ".json") {
    const Scenario s = load_scenario(input);
    const Scene initial = build_scene(s);
    return scene_at_frame(initial, s, s.frames - 1).meshes;
  }
  if (ext == ".gltf" || ext == ".glb") return import_gltf(input).meshes;
  return {generator_mesh(input.string())};
}

}  // namespace

int run_clusters_command(const ClustersCommandOptions& options) {
  ClusterDagOptions dag_options;
  dag_options.max_triangles = options.max_triangles;
  if (dag_options.max_triangles % 4 != 0 || dag_options.max_triangles == 0 || dag_options.max_triangles > 512)
    throw InputError("--max-triangles", "", "expected a multiple of 4 in 4..512 (meshoptimizer 0.18)");
  const std::vector<Mesh> meshes = meshes_of(options.input);
  nlohmann::json out = nlohmann::json::array();
  for (const Mesh& mesh : meshes) {
    const ClusterDag dag = build_cluster_dag(mesh, dag_options);
    nlohmann::json j = dag.to_json();
    j["mesh"] = mesh.name;
    j["mesh_triangles"] = mesh.triangle_count();
    j["peak_rss_mib"] = peak_rss_mib();
    if (!options.json) {
      std::printf("mesh %s: %zu triangles, %u LOD-0 clusters, %zu clusters in %u levels (ideal %u), "
                  "%u stuck (%.3f%%), built in %.2f s, peak RSS %.0f MiB, DAG hash %016llx\n",
                  mesh.name.c_str(), mesh.triangle_count(), dag.lod0_clusters, dag.clusters.size(), dag.levels,
                  dag.ideal_levels(), dag.stuck_clusters(),
                  dag.clusters.empty() ? 0.0 : 100.0 * dag.stuck_clusters() / double(dag.clusters.size()),
                  dag.build_seconds, peak_rss_mib(), static_cast<unsigned long long>(dag.content_hash()));
      // locked: share of vertices held on group borders while simplifying into
      // this level; when it nears 1 the groups stop halving (cluster_dag.h).
      std::printf("  level  clusters  triangles   fill  stuck  locked\n");
      for (const ClusterLevelStats& l : dag.level_stats())
        std::printf("  %5u  %8u  %9llu  %5.3f  %5u  %6.3f\n", l.level, l.clusters,
                    static_cast<unsigned long long>(l.triangles), l.fill, l.stuck, l.locked);
    }
    out.push_back(j);
  }
  if (options.json) std::printf("%s\n", nlohmann::json{{"input", options.input.string()}, {"meshes", out}}.dump(2).c_str());
  return 0;
}

}  // namespace gi
