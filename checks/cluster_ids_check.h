// The `cluster_ids` check (docs/design.md §6, §8): packed visibility IDs
// (`cluster_id << triangle_bits | triangle`, core/clusters/cluster_ids.h) must
// never silently overflow, as they did in Bevy 0.15 when the 1042nd cliff
// (1042 × 32 217 = 33 570 114 clusters > 2^25) was spawned.
//
// Before anything is drawn it walks the scenario's spawn and despawn events
// (event_order) adding up the IDs the visible instances own — every cluster of
// each instance's DAG — and names the first spawn that pushes the total past
// 2^cluster_bits: frame, event, instance, totals before and after. That walk
// needs no device ("count_only": true runs nothing else). When rendering, it
// also decodes every pixel's packed ID as the G-buffer resolve does and counts
// the pixels whose decoded instance differs from the independent instance
// channel (decode mismatches), per frame.
//
// Passes when no spawn overflows and no pixel mismatches. Params: cluster_bits
// (default 25), triangle_bits (7; clusters hold up to 2^triangle_bits
// triangles, ≤ 128), count_only (false), clusters_per_instance (count-only: IDs
// every instance owns, standing in for a mesh the harness does not have — the
// published cliff's 32 217 — instead of building its DAG).
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/clusters/cluster_dag.h"
#include "core/clusters/cluster_table.h"
#include "core/scenario.h"
#include "core/scene.h"
#include "checks/check_result.h"

namespace gi {

struct ClusterIdsParams {
  ClusterIdLayout layout;
  bool count_only = false;
  std::optional<std::uint32_t> clusters_per_instance;
  ClusterDagOptions dag_options() const;  // max_triangles = min(128, 2^triangle_bits)
};

// InputError at <check json_path>/<key>.
ClusterIdsParams cluster_ids_params(const CheckSpec& spec, const Scenario& scenario);

struct SpawnOverflow {
  std::uint32_t frame = 0;
  std::string event;      // JSON path of the spawn ("/events/12"), or "initial scene"
  std::string instance;
  std::uint64_t ids_before = 0, ids_after = 0, limit = 0;
  std::uint32_t spawn_number = 0;  // 1-based among the scenario's spawns (0: initial scene)
};

class ClusterIdsCheck {
 public:
  // Walks the events of frames 0 .. frames-1 (builds each mesh's DAG unless
  // clusters_per_instance is given).
  ClusterIdsCheck(ClusterIdsParams params, const Scenario& scenario, const Scene& initial, std::uint32_t frames);

  const ClusterIdsParams& params() const { return params_; }
  const std::optional<SpawnOverflow>& overflow() const { return overflow_; }
  std::uint64_t peak_ids() const { return peak_ids_; }

  // The renderer's ID space for `scene` (its meshes' DAGs) over its flattened geometry.
  std::vector<MeshClusterIds> mesh_cluster_ids(const Scene& scene, const FlatGeometry& geometry);
  // After frame `frame` is drawn: decoded IDs against the instance channel.
  // packed: Renderer::packed_visibility(); table: Renderer::cluster_table();
  // scene: the frame's (names the instance whose pixels first decode wrong).
  nlohmann::json record_frame(std::uint32_t frame, const std::vector<glm::uvec2>& packed,
                              const std::vector<std::uint32_t>& table, const Scene& scene);
  CheckResult result() const;

 private:
  const ClusterDag& dag(const Scene& scene, std::uint32_t mesh);
  std::uint64_t ids_of(const Scene& scene, std::uint32_t mesh);

  ClusterIdsParams params_;
  std::map<std::uint32_t, ClusterDag> dags_;  // by mesh index (meshes are only ever appended)
  std::optional<SpawnOverflow> overflow_;
  std::uint64_t peak_ids_ = 0;
  std::uint32_t spawns_ = 0;
  bool rendered_ = false;
  std::uint64_t mismatches_ = 0, mismatches_before_overflow_ = 0;
  std::optional<std::uint32_t> first_mismatch_frame_;
  // What the rendered buffer alone says: on the first frame with wrong
  // pixels, the instance (channel) most of them belong to, and how many.
  struct RenderedOverflow {
    std::uint32_t frame = 0, instance = 0, spawn_number = 0;  // spawn_number 0: an initial instance
    std::string name;
    std::uint64_t pixels = 0;
  };
  std::optional<RenderedOverflow> rendered_overflow_;
  std::uint32_t initial_instances_ = 0;
  std::uint32_t frames_drawn_ = 0, frames_over_limit_ = 0;
};

// A count_only cluster_ids check decides the run alone: it walks the spawns
// and counts IDs, with no device and nothing drawn. Every other check of the
// scenario is refused (InputError): they need a drawn frame.
void refuse_checks_beside_count_only(const Scenario& scenario);
CheckResult count_only_result(const ClusterIdsParams& params, const Scenario& scenario, const Scene& initial,
                              std::uint32_t frames);

}  // namespace gi
