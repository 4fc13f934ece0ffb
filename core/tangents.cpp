// MikkTSpace, step by step (the names of mikktspace.c's functions in brackets,
// for a reader holding the original next to this):
//  1. weld corners with identical position, normal and uv into vertices
//     [GenerateSharedVerticesIndexList];
//  2. set aside triangles with two corners on one vertex [DegenPrologue];
//  3. per triangle, the first-order derivatives of position over uv: the
//     directions of increasing u and v, their magnitudes and whether the uv
//     mapping preserves the triangle's winding [InitTriInfo];
//  4. link triangles across shared, oppositely wound edges [BuildNeighborsFast];
//  5. per vertex, group the triangles around it that are reachable through
//     neighbours of the same orientation: mirrored uvs split a vertex's fan
//     [Build4RuleGroups, AssignRecur];
//  6. per corner, the angle-weighted average over its group of the
//     triangles' tangent directions projected onto the corner's tangent plane
//     [GenerateTSpaces, EvalTspace];
//  7. degenerate triangles' corners copy a good corner at the same vertex
//     [DegenEpilogue].
// Only triangles: mikktspace.c's quad handling never applies to a triangle list.
#include "core/tangents.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>

namespace gi {
namespace {

constexpr int kNone = -1;

// MikkTSpace's default angular threshold is 180°, whose cosine (as float) is
// -1: two triangles' tangent directions at a vertex stay in one sub-group
// unless they point exactly opposite.
constexpr float kSubgroupThresholdCos = -1.0f;

// mikktspace.c's notion of zero: anything at or below the smallest normal float.
bool not_zero(float x) { return std::fabs(x) > FLT_MIN; }
bool not_zero(const glm::vec3& v) { return not_zero(v.x) || not_zero(v.y) || not_zero(v.z); }

glm::vec3 normalized_unless_zero(const glm::vec3& v) { return not_zero(v) ? v / glm::length(v) : v; }

// v without its component along the unit normal n, then unit length (left as
// is when nothing is left): a direction in n's tangent plane.
glm::vec3 in_tangent_plane(const glm::vec3& v, const glm::vec3& n) {
  return normalized_unless_zero(v - glm::dot(n, v) * n);
}

// ---------------------------------------------------------------------------
// 1. Welding.

struct WeldedMesh {
  std::vector<std::uint32_t> vertex_of_corner;  // one per mesh index
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // unit length (the projections assume it)
  std::vector<glm::vec2> uvs;
};

void check_inputs(const Mesh& mesh) {
  const std::string what = "generate_tangents: mesh '" + mesh.name + "' ";
  if (mesh.normals.size() != mesh.positions.size())
    throw std::invalid_argument(what + "needs one normal per position");
  if (mesh.uvs.size() != mesh.positions.size())
    throw std::invalid_argument(what + "needs one uv (TEXCOORD_0) per position");
  if (mesh.indices.size() % 3 != 0) throw std::invalid_argument(what + "has a partial triangle");
  for (const std::uint32_t index : mesh.indices)
    if (index >= mesh.positions.size()) throw std::invalid_argument(what + "has an index out of range");
}

// Vertices numbered in order of first use, so the numbering (and every
// order-dependent step after it) depends on the input alone. The key compares
// floats with <, so -0 and +0 weld, as mikktspace.c's == does.
WeldedMesh weld_corners(const Mesh& mesh) {
  WeldedMesh welded;
  std::map<std::array<float, 8>, std::uint32_t> vertex_of_key;
  welded.vertex_of_corner.reserve(mesh.indices.size());
  for (const std::uint32_t index : mesh.indices) {
    const glm::vec3& p = mesh.positions[index];
    const glm::vec3& n = mesh.normals[index];
    const glm::vec2& uv = mesh.uvs[index];
    const std::array<float, 8> key{p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y};
    const auto [it, inserted] = vertex_of_key.try_emplace(key, std::uint32_t(welded.positions.size()));
    if (inserted) {
      welded.positions.push_back(p);
      welded.normals.push_back(normalized_unless_zero(n));
      welded.uvs.push_back(uv);
    }
    welded.vertex_of_corner.push_back(it->second);
  }
  return welded;
}

// ---------------------------------------------------------------------------
// 2.-3. Triangles and their first-order derivatives.

struct Triangle {
  std::array<std::uint32_t, 3> vertex{};  // welded vertices
  std::uint32_t first_corner = 0;         // 3 × the face's number in the input
  glm::vec3 u_direction{0.0f};            // unit ∂p/∂u (zero without uv area)
  glm::vec3 v_direction{0.0f};            // unit ∂p/∂v
  bool orientation_preserving = false;    // the uv triangle winds as the corners do (positive uv area)
  bool group_with_any = true;             // no usable uv derivative: joins any neighbour's group
  std::array<int, 3> neighbour{kNone, kNone, kNone};  // across edge (k, k+1)
  std::array<int, 3> group{kNone, kNone, kNone};      // at corner k
};

bool is_degenerate(const std::array<std::uint32_t, 3>& v) { return v[0] == v[1] || v[1] == v[2] || v[0] == v[2]; }

// Position as a linear function of uv over the triangle: solving
// d1 = ∂p/∂u·Δu1 + ∂p/∂v·Δv1, d2 = ∂p/∂u·Δu2 + ∂p/∂v·Δv2 by Cramer's rule gives
// os = ∂p/∂u and ot = ∂p/∂v times the signed uv area (×2). Normalising with
// that area's sign gives the true directions, mirrored uvs included.
void derive_uv_frame(Triangle& tri, const WeldedMesh& welded) {
  const glm::vec3& p0 = welded.positions[tri.vertex[0]];
  const glm::vec2& t0 = welded.uvs[tri.vertex[0]];
  const glm::vec3 d1 = welded.positions[tri.vertex[1]] - p0;
  const glm::vec3 d2 = welded.positions[tri.vertex[2]] - p0;
  const glm::vec2 t21 = welded.uvs[tri.vertex[1]] - t0;
  const glm::vec2 t31 = welded.uvs[tri.vertex[2]] - t0;
  const float signed_uv_area_x2 = t21.x * t31.y - t21.y * t31.x;
  const glm::vec3 os = t31.y * d1 - t21.y * d2;
  const glm::vec3 ot = -t31.x * d1 + t21.x * d2;
  tri.orientation_preserving = signed_uv_area_x2 > 0.0f;
  if (!not_zero(signed_uv_area_x2)) return;  // no uv area: no derivative, directions stay zero

  const float sign = tri.orientation_preserving ? 1.0f : -1.0f;
  const float os_length = glm::length(os);
  const float ot_length = glm::length(ot);
  tri.u_direction = not_zero(os_length) ? (sign / os_length) * os : os;
  tri.v_direction = not_zero(ot_length) ? (sign / ot_length) * ot : ot;
  // |∂p/∂u| and |∂p/∂v|: a triangle whose uvs stretch to nothing along one
  // axis has no usable frame. (mikktspace.c also averages these magnitudes
  // for its full output, which a glTF TANGENT has no room for.)
  const float u_magnitude = os_length / std::fabs(signed_uv_area_x2);
  const float v_magnitude = ot_length / std::fabs(signed_uv_area_x2);
  if (not_zero(u_magnitude) && not_zero(v_magnitude)) tri.group_with_any = false;
}

struct DegenerateTriangle {
  std::array<std::uint32_t, 3> vertex{};
  std::uint32_t first_corner = 0;
};

struct Triangles {
  std::vector<Triangle> good;  // in input order
  std::vector<DegenerateTriangle> degenerate;
};

Triangles classify_triangles(const WeldedMesh& welded) {
  Triangles triangles;
  const std::size_t count = welded.vertex_of_corner.size() / 3;
  for (std::size_t face = 0; face < count; ++face) {
    Triangle tri;
    tri.first_corner = std::uint32_t(3 * face);
    for (int k = 0; k < 3; ++k) tri.vertex[k] = welded.vertex_of_corner[3 * face + k];
    if (is_degenerate(tri.vertex)) {
      triangles.degenerate.push_back({tri.vertex, tri.first_corner});
      continue;
    }
    derive_uv_frame(tri, welded);
    triangles.good.push_back(tri);
  }
  return triangles;
}

// ---------------------------------------------------------------------------
// 4. Neighbours.

struct Edge {
  std::uint32_t low, high;  // the edge's vertices, sorted
  int triangle;
  int number;  // k: from corner k to corner k+1
  auto key() const { return std::tuple(low, high, triangle); }
};

// Sorted by (low vertex, high vertex, triangle), each still unpaired edge is
// paired with the first later unpaired edge that runs the other way, as
// mikktspace.c does (which decides where more than two triangles share an edge).
void link_neighbours(std::vector<Triangle>& tris) {
  std::vector<Edge> edges;
  edges.reserve(3 * tris.size());
  for (int t = 0; t < int(tris.size()); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tris[t].vertex[k], b = tris[t].vertex[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), t, k});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) { return x.key() < y.key(); });

  for (std::size_t i = 0; i < edges.size(); ++i) {
    Triangle& a = tris[edges[i].triangle];
    const int ka = edges[i].number;
    if (a.neighbour[ka] != kNone) continue;
    for (std::size_t j = i + 1; j < edges.size() && edges[j].low == edges[i].low && edges[j].high == edges[i].high; ++j) {
      Triangle& b = tris[edges[j].triangle];
      const int kb = edges[j].number;
      const bool runs_opposite = a.vertex[ka] == b.vertex[(kb + 1) % 3] && a.vertex[(ka + 1) % 3] == b.vertex[kb];
      if (runs_opposite && b.neighbour[kb] == kNone) {
        a.neighbour[ka] = edges[j].triangle;
        b.neighbour[kb] = edges[i].triangle;
        break;
      }
    }
  }
}

// ---------------------------------------------------------------------------
// 5. Groups: per vertex, the fan of triangles reachable across neighbours
// without crossing a change of orientation.

struct Group {
  std::uint32_t vertex = 0;
  bool orientation_preserving = false;
  std::vector<int> triangles;  // in the order they joined
};

int corner_at_vertex(const Triangle& tri, std::uint32_t vertex) {
  for (int k = 0; k < 3; ++k)
    if (tri.vertex[k] == vertex) return k;
  return kNone;
}

class GroupBuilder {
 public:
  explicit GroupBuilder(std::vector<Triangle>& tris) : tris_(tris) {}

  // Every corner of every triangle with a uv derivative seeds a group (unless
  // already in one); triangles without one only join through neighbours.
  std::vector<Group> build() {
    for (int t = 0; t < int(tris_.size()); ++t) {
      if (tris_[t].group_with_any) continue;
      for (int k = 0; k < 3; ++k) {
        if (tris_[t].group[k] != kNone) continue;
        const int g = int(groups_.size());
        groups_.push_back({tris_[t].vertex[k], tris_[t].orientation_preserving, {}});
        tris_[t].group[k] = g;
        groups_[g].triangles.push_back(t);
        spread_to_neighbours_of(t, k, g);
      }
    }
    return std::move(groups_);
  }

 private:
  // The two neighbours across corner k's two edges share its vertex.
  void spread_to_neighbours_of(int t, int k, int g) {
    const int across_next_edge = tris_[t].neighbour[k];
    const int across_previous_edge = tris_[t].neighbour[(k + 2) % 3];
    if (across_next_edge != kNone) assign(across_next_edge, g);
    if (across_previous_edge != kNone) assign(across_previous_edge, g);
  }

  void assign(int t, int g) {
    Triangle& tri = tris_[t];
    const int k = corner_at_vertex(tri, groups_[g].vertex);
    if (k == kNone || tri.group[k] != kNone) return;  // (k is always found: the neighbour shares the vertex)
    // A triangle without a uv derivative takes the orientation of the first
    // group that reaches it (mikktspace.c's one order dependency).
    const bool untouched = tri.group[0] == kNone && tri.group[1] == kNone && tri.group[2] == kNone;
    if (tri.group_with_any && untouched) tri.orientation_preserving = groups_[g].orientation_preserving;
    if (tri.orientation_preserving != groups_[g].orientation_preserving) return;  // a mirror seam
    groups_[g].triangles.push_back(t);
    tri.group[k] = g;
    spread_to_neighbours_of(t, k, g);
  }

  std::vector<Triangle>& tris_;
  std::vector<Group> groups_;
};

// ---------------------------------------------------------------------------
// 6. Tangent per corner.

struct CornerFrame {
  // mikktspace.c's value for a corner it never reaches (a degenerate
  // triangle alone at its vertices, a uv-less triangle no group reached).
  glm::vec3 tangent{1.0f, 0.0f, 0.0f};
  bool orientation_preserving = false;
};

// Corner k of triangle tri: the angle between its two edges, both projected
// onto the tangent plane of the normal n: the corner's weight in the average.
float corner_angle(const Triangle& tri, int k, const glm::vec3& n, const WeldedMesh& welded) {
  const glm::vec3& p = welded.positions[tri.vertex[k]];
  const glm::vec3 to_previous = in_tangent_plane(welded.positions[tri.vertex[(k + 2) % 3]] - p, n);
  const glm::vec3 to_next = in_tangent_plane(welded.positions[tri.vertex[(k + 1) % 3]] - p, n);
  return std::acos(std::clamp(glm::dot(to_previous, to_next), -1.0f, 1.0f));
}

// The tangent of a sub-group at its vertex: the angle-weighted sum of each
// member's u direction projected onto the vertex's tangent plane. Triangles
// without a uv derivative belong to the group but do not vote.
glm::vec3 subgroup_tangent(const std::vector<int>& members, std::uint32_t vertex, const std::vector<Triangle>& tris,
                           const WeldedMesh& welded) {
  const glm::vec3& n = welded.normals[vertex];
  glm::vec3 sum{0.0f};
  for (const int t : members) {
    const Triangle& tri = tris[t];
    if (tri.group_with_any) continue;
    sum += corner_angle(tri, corner_at_vertex(tri, vertex), n, welded) * in_tangent_plane(tri.u_direction, n);
  }
  return normalized_unless_zero(sum);
}

// Within a group, the members whose u and v directions at the vertex both lie
// within the threshold of triangle f's (always f itself). Sorted, so equal
// sub-groups compare equal.
std::vector<int> subgroup_of(int f, const Group& group, const std::vector<Triangle>& tris, const glm::vec3& n) {
  const glm::vec3 os = in_tangent_plane(tris[f].u_direction, n);
  const glm::vec3 ot = in_tangent_plane(tris[f].v_direction, n);
  std::vector<int> members;
  for (const int t : group.triangles) {
    const bool any = tris[f].group_with_any || tris[t].group_with_any;
    const bool close = glm::dot(os, in_tangent_plane(tris[t].u_direction, n)) > kSubgroupThresholdCos &&
                       glm::dot(ot, in_tangent_plane(tris[t].v_direction, n)) > kSubgroupThresholdCos;
    if (any || t == f || close) members.push_back(t);
  }
  std::sort(members.begin(), members.end());
  return members;
}

void frames_of_group(const Group& group, const std::vector<Triangle>& tris, const WeldedMesh& welded,
                     std::vector<CornerFrame>& frames) {
  const glm::vec3& n = welded.normals[group.vertex];
  std::vector<std::vector<int>> subgroups;  // distinct ones, each evaluated once
  std::vector<glm::vec3> subgroup_tangents;
  for (const int f : group.triangles) {
    std::vector<int> members = subgroup_of(f, group, tris, n);
    const auto found = std::find(subgroups.begin(), subgroups.end(), members);
    const std::size_t s = std::size_t(found - subgroups.begin());
    if (found == subgroups.end()) {
      subgroup_tangents.push_back(subgroup_tangent(members, group.vertex, tris, welded));
      subgroups.push_back(std::move(members));
    }
    const int k = corner_at_vertex(tris[f], group.vertex);
    frames[tris[f].first_corner + k] = {subgroup_tangents[s], group.orientation_preserving};
  }
}

// ---------------------------------------------------------------------------
// 7. Degenerate triangles: each corner copies the first good corner (in input
// order) on the same vertex.

void copy_frames_to_degenerate_corners(const Triangles& triangles, std::size_t vertex_count,
                                       std::vector<CornerFrame>& frames) {
  std::vector<int> first_good_corner(vertex_count, kNone);
  for (const Triangle& tri : triangles.good)
    for (int k = 0; k < 3; ++k)
      if (first_good_corner[tri.vertex[k]] == kNone) first_good_corner[tri.vertex[k]] = int(tri.first_corner) + k;
  for (const DegenerateTriangle& tri : triangles.degenerate)
    for (int k = 0; k < 3; ++k) {
      const int source = first_good_corner[tri.vertex[k]];
      if (source != kNone) frames[tri.first_corner + k] = frames[source];
    }
}

// Any unit vector orthogonal to n (for corners whose tangent vanished in the
// projection, or that MikkTSpace never reached); +x for a zero normal.
glm::vec3 any_perpendicular(const glm::vec3& n) {
  const glm::vec3 axis = std::fabs(n.x) < 0.9f * glm::length(n) ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
  const glm::vec3 perpendicular = glm::cross(n, axis);
  return not_zero(perpendicular) ? glm::normalize(perpendicular) : glm::vec3(1.0f, 0.0f, 0.0f);
}

// Gram-Schmidt against the normal: a no-op (to rounding) for MikkTSpace's own
// tangents, which it already projected, and a repair for the fallbacks. The
// sign is negated into glTF's convention (see tangents.h).
glm::vec4 gltf_tangent(const CornerFrame& frame, const glm::vec3& n) {
  glm::vec3 t = frame.tangent - glm::dot(n, frame.tangent) * n;
  const float length = glm::length(t);
  t = length > 1e-6f ? t / length : any_perpendicular(n);
  return {t, frame.orientation_preserving ? -1.0f : 1.0f};
}

}  // namespace

std::vector<glm::vec4> mikktspace_corner_tangents(const Mesh& mesh) {
  check_inputs(mesh);
  const WeldedMesh welded = weld_corners(mesh);
  Triangles triangles = classify_triangles(welded);
  link_neighbours(triangles.good);
  const std::vector<Group> groups = GroupBuilder(triangles.good).build();

  std::vector<CornerFrame> frames(mesh.indices.size());
  for (const Group& group : groups) frames_of_group(group, triangles.good, welded, frames);
  copy_frames_to_degenerate_corners(triangles, welded.positions.size(), frames);

  std::vector<glm::vec4> tangents(frames.size());
  for (std::size_t c = 0; c < frames.size(); ++c)
    tangents[c] = gltf_tangent(frames[c], welded.normals[welded.vertex_of_corner[c]]);
  return tangents;
}

void generate_tangents(Mesh& mesh) {
  const std::vector<glm::vec4> corner_tangents = mikktspace_corner_tangents(mesh);
  const std::size_t original_count = mesh.positions.size();

  // Per original vertex, the tangents it has been given so far and the vertex
  // carrying each: the first keeps the original, others get copies.
  std::vector<std::vector<std::pair<glm::vec4, std::uint32_t>>> variants(original_count);
  mesh.tangents.assign(original_count, glm::vec4(0.0f));
  for (std::size_t c = 0; c < mesh.indices.size(); ++c) {
    const std::uint32_t v = mesh.indices[c];
    const glm::vec4& tangent = corner_tangents[c];
    auto& known = variants[v];
    const auto same = std::find_if(known.begin(), known.end(), [&](const auto& k) { return k.first == tangent; });
    if (same != known.end()) {
      mesh.indices[c] = same->second;
      continue;
    }
    std::uint32_t target = v;
    if (!known.empty()) {  // a different tangent on a used vertex: split it
      target = std::uint32_t(mesh.positions.size());
      mesh.positions.push_back(mesh.positions[v]);
      mesh.normals.push_back(mesh.normals[v]);
      mesh.uvs.push_back(mesh.uvs[v]);
      mesh.tangents.push_back(tangent);
    }
    mesh.tangents[target] = tangent;
    mesh.indices[c] = target;
    known.emplace_back(tangent, target);
  }
  for (std::size_t v = 0; v < original_count; ++v)
    if (variants[v].empty()) mesh.tangents[v] = glm::vec4(any_perpendicular(mesh.normals[v]), 1.0f);
}

}  // namespace gi
