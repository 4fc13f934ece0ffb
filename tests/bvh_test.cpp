// The `bvh` backend on the CPU: the binned-SAH builder's invariants and
// determinism, the TLAS rebuild policy, the watertight triangle test (shown
// to matter: a Möller-Trumbore test leaks through shared edges that it
// closes), and the CPU twin of the GPU traversal against Embree.
#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "core/bvh/bvh_builder.h"
#include "core/errors.h"
#include "core/bvh/bvh_cpu_tracer.h"
#include "core/bvh/embree_ray_caster.h"
#include "core/bvh/ray_sets.h"
#include "core/bvh/scene_bvh.h"
#include "core/scene_flatten.h"
#include "core/scenes/cliff.h"
#include "core/scenes/cornell_box.h"
#include "core/shared/rng.h"
#include "core/shared/watertight.h"

namespace {

using gi::bvh::Aabb;
using gi::shader::BvhNode;

bool contains(const glm::vec3& lo, const glm::vec3& hi, const Aabb& b) {
  return glm::all(glm::lessThanEqual(lo, b.lo)) && glm::all(glm::lessThanEqual(b.hi, hi));
}

// Child c's box as the traversal dequantises it (bvh_ray_box4).
Aabb child_box(const BvhNode& n, int c) {
  Aabb b;
  for (std::uint32_t k = 0; k < 3; ++k) {
    const float step = gi::shader::bvh_grid_step(n.scale_bits, k);
    b.lo[k] = n.origin[k] + float((n.q_lo[k] >> (8 * c)) & 0xffu) * step;
    b.hi[k] = n.origin[k] + float((n.q_hi[k] >> (8 * c)) & 0xffu) * step;
  }
  return b;
}

// Walks the 4-wide tree: every primitive sits in exactly one leaf, inside the
// (quantised, so only conservative) box of every node on its path. Returns
// the deepest stack the traversal could use, as the builder bounds it.
std::uint32_t check_tree(const gi::bvh::BuiltBvh& tree, const std::vector<Aabb>& boxes, std::uint32_t node = 0,
                         glm::vec3 lo = glm::vec3(-1e30f), glm::vec3 hi = glm::vec3(1e30f),
                         std::multiset<std::uint32_t>* seen = nullptr) {
  std::multiset<std::uint32_t> own;
  if (!seen) seen = &own;
  const BvhNode& n = tree.nodes.at(node);
  std::uint32_t inner = 0, deepest = 0;
  bool empty_seen = false;
  for (int c = 0; c < 4; ++c) {
    const std::uint32_t ch = n.child[c];
    if (ch == gi::shader::BVH_CHILD_EMPTY) {
      empty_seen = true;
      continue;
    }
    EXPECT_FALSE(empty_seen) << "empty slots come last";
    const Aabb b = child_box(n, c);
    const glm::vec3 clo = glm::max(lo, b.lo), chi = glm::min(hi, b.hi);  // every ancestor's box
    if (!gi::shader::bvh_is_leaf(ch)) {
      ++inner;
      deepest = std::max(deepest, check_tree(tree, boxes, ch, clo, chi, seen));
      continue;
    }
    const std::uint32_t first = gi::shader::bvh_leaf_first(ch);
    for (std::uint32_t k = first; k < first + gi::shader::bvh_leaf_count(ch); ++k) {
      const std::uint32_t prim = tree.order.at(k);
      seen->insert(prim);
      EXPECT_TRUE(contains(clo, chi, boxes[prim])) << "primitive " << prim;
    }
  }
  const std::uint32_t need = (inner > 0 ? inner - 1 : 0) + deepest;
  if (seen == &own) {
    EXPECT_EQ(need, tree.stack_need);
    EXPECT_EQ(seen->size(), boxes.size());
    std::uint32_t expect = 0;
    for (std::uint32_t p : *seen) EXPECT_EQ(p, expect++) << "every primitive exactly once";
  }
  return need;
}

std::vector<Aabb> triangle_boxes(const gi::Mesh& mesh) {
  std::vector<Aabb> boxes(mesh.triangle_count());
  for (std::size_t t = 0; t < boxes.size(); ++t)
    for (int k = 0; k < 3; ++k) boxes[t].grow(mesh.positions[mesh.indices[3 * t + k]]);
  return boxes;
}

TEST(BvhBuilder, EveryTriangleInOneLeafInsideNestedBoxes) {
  gi::CliffOptions o;
  o.triangles = 5000;
  const std::vector<Aabb> boxes = triangle_boxes(gi::make_cliff_mesh(o));
  const gi::bvh::BuiltBvh tree = gi::bvh::build_bvh(boxes);
  check_tree(tree, boxes);
  EXPECT_LE(tree.stack_need, gi::shader::BVH_BLAS_STACK_SIZE);
  EXPECT_GT(tree.nodes.size(), boxes.size() / 32) << "leaves hold at most a few triangles";
  // Quantised boxes stay tight: leaf boxes are on average barely larger than
  // the boxes of their triangles, so traversal visits few extra nodes.
  double stored_area = 0.0, true_area = 0.0;
  for (const BvhNode& n : tree.nodes)
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t ch = n.child[c];
      if (ch == gi::shader::BVH_CHILD_EMPTY || !gi::shader::bvh_is_leaf(ch)) continue;
      Aabb contents;
      const std::uint32_t first = gi::shader::bvh_leaf_first(ch);
      for (std::uint32_t k = first; k < first + gi::shader::bvh_leaf_count(ch); ++k)
        contents.grow(boxes[tree.order[k]]);
      stored_area += child_box(n, c).half_area();
      true_area += contents.half_area();
    }
  std::printf("leaf box area: quantised / exact = %.4f\n", stored_area / true_area);
  EXPECT_LT(stored_area, 1.25 * true_area);
}

TEST(BvhBuilder, SmallAndDegenerateInputs) {
  // Empty: one root whose children are all empty.
  const gi::bvh::BuiltBvh empty = gi::bvh::build_bvh({});
  ASSERT_EQ(empty.nodes.size(), 1u);
  EXPECT_EQ(empty.nodes[0].child, glm::uvec4(gi::shader::BVH_CHILD_EMPTY));
  // One primitive: a root with the leaf on the left.
  std::vector<Aabb> one(1);
  one[0].grow(glm::vec3(0.0f));
  one[0].grow(glm::vec3(1.0f));
  check_tree(gi::bvh::build_bvh(one), one);
  // 1000 identical boxes (coincident centroids): median splits keep leaves small.
  std::vector<Aabb> same(1000, one[0]);
  const gi::bvh::BuiltBvh tree = gi::bvh::build_bvh(same);
  check_tree(tree, same);
  EXPECT_LE(tree.depth, 12u);
  // Boxes far from the origin, tiny and huge, all quantise conservatively.
  std::vector<Aabb> odd;
  for (int i = 0; i < 200; ++i) {
    Aabb b;
    const float base = (i % 3 == 0 ? 1e6f : i % 3 == 1 ? -3.7e4f : 1e-3f) + 1.37f * float(i);
    const float size = i % 4 == 0 ? 0.0f : i % 4 == 1 ? 1e-6f : i % 4 == 2 ? 0.5f : 1e4f;
    b.grow(glm::vec3(base, -base, 0.5f * base));
    b.grow(glm::vec3(base + size, -base + 0.3f * size, 0.5f * base - size));
    odd.push_back(b);
  }
  check_tree(gi::bvh::build_bvh(odd), odd);
}

TEST(BvhBuilder, SameInputSameBytes) {
  gi::CliffOptions o;
  o.triangles = 3000;
  const std::vector<Aabb> boxes = triangle_boxes(gi::make_cliff_mesh(o));
  const auto a = gi::bvh::build_bvh(boxes), b = gi::bvh::build_bvh(boxes);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)), 0);
  EXPECT_EQ(a.order, b.order);
}

TEST(SceneBvh, RebuildsTheTlasOnlyWhenTransformsOrVisibilityChange) {
  gi::Scene scene = gi::make_cornell_box();
  const gi::FlatGeometry geometry = gi::flatten_geometry(scene);
  gi::FlatInstances flat = gi::flatten_instances(scene, geometry);
  std::vector<bool> visible = scene.visible_instances();
  gi::bvh::SceneBvh bvh(geometry);
  EXPECT_TRUE(bvh.update(flat.instances, visible));
  EXPECT_FALSE(bvh.update(flat.instances, visible)) << "nothing changed";
  flat.materials[0].base_color_metallic = glm::vec4(0.1f);  // not geometry
  EXPECT_FALSE(bvh.update(flat.instances, visible));
  const std::uint32_t tall = *scene.find_instance("tall_block");
  flat.instances[tall].object_to_world =
      glm::translate(glm::mat4(1.0f), glm::vec3(100.0f, 0.0f, 0.0f)) * flat.instances[tall].object_to_world;
  EXPECT_TRUE(bvh.update(flat.instances, visible)) << "a transform changed";
  visible[tall] = false;
  EXPECT_TRUE(bvh.update(flat.instances, visible)) << "the visible set changed";
  EXPECT_FALSE(bvh.update(flat.instances, visible));
  EXPECT_EQ(bvh.tlas_builds(), 3u);
  EXPECT_EQ(bvh.tlas_instance_count(), flat.instances.size() - 1);
}

// A spawned mesh (add_meshes) gives the same bytes as a structure built with
// it from the start, so a replay that rebuilds the scene at a later frame
// traces exactly what the run traced; the earlier meshes are kept, and the
// next update rebuilds the TLAS.
TEST(SceneBvh, AddedMeshesMatchAFreshBuild) {
  gi::Scene scene = gi::make_cornell_box();
  const gi::FlatGeometry before = gi::flatten_geometry(scene);
  gi::CliffOptions rock;
  rock.triangles = 300;
  rock.width = 0.2f;
  rock.height = 0.1f;
  rock.depth = 0.1f;
  scene.meshes.push_back(gi::make_cliff_mesh(rock));
  scene.materials.push_back(gi::make_cliff_material());
  gi::Instance inst;
  inst.name = "rock";
  inst.mesh = std::uint32_t(scene.meshes.size() - 1);
  inst.material = std::uint32_t(scene.materials.size() - 1);
  inst.transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 0.0f, 0.25f));
  scene.instances.push_back(inst);
  const gi::FlatGeometry after = gi::flatten_geometry(scene);
  const gi::FlatInstances flat = gi::flatten_instances(scene, after);
  std::vector<bool> visible = scene.visible_instances();
  std::vector<bool> old_visible = visible;
  old_visible.back() = false;  // before the spawn

  gi::bvh::SceneBvh grown(before);
  EXPECT_TRUE(grown.update(flat.instances, old_visible));
  const std::size_t old_triangles = grown.triangles().size();
  grown.add_meshes(after);
  EXPECT_TRUE(grown.update(flat.instances, visible)) << "the TLAS is rebuilt over the new instance";
  gi::bvh::SceneBvh fresh(after);
  fresh.update(flat.instances, visible);
  ASSERT_GT(grown.triangles().size(), old_triangles);
  ASSERT_EQ(grown.triangles().size(), fresh.triangles().size());
  EXPECT_EQ(std::memcmp(grown.triangles().data(), fresh.triangles().data(),
                        fresh.triangles().size() * sizeof(fresh.triangles()[0])), 0);
  // The node layouts differ (the grown one doubled its TLAS capacity); what
  // a ray meets does not, bit for bit.
  gi::bvh::RaySetOptions options;
  options.count = 20000;
  options.camera = gi::make_gpu_camera(scene.camera, 64, 64);
  std::size_t rock_hits = 0;
  for (const gi::bvh::TraceRay& ray : gi::bvh::make_ray_set(after, flat, visible, options)) {
    gi::shader::Hit a{}, b{};
    const bool hit_a = gi::shader::BvhCpuTracer(grown).bvh_trace(ray.origin, ray.direction, ray.tmax, false, a);
    const bool hit_b = gi::shader::BvhCpuTracer(fresh).bvh_trace(ray.origin, ray.direction, ray.tmax, false, b);
    ASSERT_EQ(hit_a, hit_b);
    if (!hit_a) continue;
    ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0);
    rock_hits += a.instance == flat.instances.size() - 1;
  }
  EXPECT_GT(rock_hits, 0u) << "the spawned rock is hit";
  // A mesh that changed (not appended) is refused.
  gi::FlatGeometry changed = after;
  changed.meshes[0].triangle_count -= 1;
  EXPECT_THROW(grown.add_meshes(changed), gi::DeviceError);
}

// A hidden instance is not hit; shown again, it is.
TEST(SceneBvh, HiddenInstancesAreNotHit) {
  gi::Scene scene = gi::make_cornell_box();
  const gi::FlatGeometry geometry = gi::flatten_geometry(scene);
  const gi::FlatInstances flat = gi::flatten_instances(scene, geometry);
  std::vector<bool> visible = scene.visible_instances();
  gi::bvh::SceneBvh bvh(geometry);
  bvh.update(flat.instances, visible);
  const gi::GpuCamera cam = gi::make_gpu_camera(scene.camera, 1, 1);
  const glm::vec3 o(cam.position), d(cam.forward);
  gi::shader::Hit first;
  ASSERT_TRUE(gi::shader::BvhCpuTracer(bvh).bvh_trace(o, d, 1e20f, false, first));
  visible[first.instance] = false;
  bvh.update(flat.instances, visible);
  gi::shader::Hit second;
  ASSERT_TRUE(gi::shader::BvhCpuTracer(bvh).bvh_trace(o, d, 1e20f, false, second));
  EXPECT_NE(second.instance, first.instance);
  EXPECT_GT(second.t, first.t);
}

// Möller-Trumbore, the non-watertight test a simple compute BVH would use.
bool moller_trumbore(glm::vec3 o, glm::vec3 d, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2) {
  const glm::vec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
  const float det = glm::dot(e1, pv);
  if (det == 0.0f) return false;
  const float inv = 1.0f / det;
  const glm::vec3 tv = o - p0;
  const float u = glm::dot(tv, pv) * inv;
  if (u < 0.0f || u > 1.0f) return false;
  const glm::vec3 qv = glm::cross(tv, e1);
  const float v = glm::dot(d, qv) * inv;
  if (v < 0.0f || u + v > 1.0f) return false;
  return glm::dot(e2, qv) * inv > 0.0f;
}

// Rays aimed exactly at points of shared edges of a tilted, irregular grid:
// each must hit one of the grid's triangles. The watertight test never lets
// one through; Möller-Trumbore does (which is why the backend uses Woop's).
TEST(Watertight, NoRayThroughSharedEdgesWhereMollerTrumboreLeaks) {
  const int n = 24;
  std::vector<glm::vec3> grid;
  std::uint32_t state = 99;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const glm::vec2 jitter = gi::shader::rng_next_vec2(state) * 0.3f;
      grid.push_back(glm::vec3(i + jitter.x, j + jitter.y, 0.37f * i - 0.21f * j + jitter.x));
    }
  std::vector<glm::uvec3> tris;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      tris.push_back({a, b, d});
      tris.push_back({a, d, c});
    }
  int watertight_leaks = 0, mt_leaks = 0, rays = 0;
  for (const glm::uvec3& t : tris)
    for (int e = 0; e < 3; ++e) {
      const glm::vec3 p = grid[t[e]], q = grid[t[(e + 1) % 3]];
      for (int s = 1; s < 8; ++s) {
        const glm::vec3 target = glm::mix(p, q, float(s) / 8.0f);
        const glm::vec3 origin(target.x * 0.93f + 0.71f, target.y * 1.07f - 0.37f, 40.0f + 0.13f * s);
        const glm::vec3 dir = glm::normalize(target - origin);
        if (target.x <= 0.5f || target.y <= 0.5f || target.x >= n - 0.5f || target.y >= n - 0.5f) continue;
        ++rays;
        bool hit_wt = false, hit_mt = false;
        const gi::shader::WatertightRay wr = gi::shader::watertight_ray(origin, dir);
        for (const glm::uvec3& u : tris) {
          float th;
          glm::vec2 b;
          hit_wt = hit_wt || gi::shader::watertight_triangle(wr, grid[u.x], grid[u.y], grid[u.z], 1e20f, th, b);
          hit_mt = hit_mt || moller_trumbore(origin, dir, grid[u.x], grid[u.y], grid[u.z]);
        }
        watertight_leaks += !hit_wt;
        mt_leaks += !hit_mt;
      }
    }
  std::printf("%d rays at shared edges: watertight leaks %d, Moller-Trumbore leaks %d\n", rays, watertight_leaks,
              mt_leaks);
  EXPECT_EQ(watertight_leaks, 0);
  EXPECT_GT(mt_leaks, 0) << "the edge rays should be hard enough to catch a non-watertight test";
}

// The CPU twin of the GPU traversal against Embree (robust mode) on a dense
// procedural mesh: the same hits and t within 1e-4.
TEST(BvhCpuTwin, AgreesWithEmbreeOnACliff) {
  gi::CliffOptions o;
  o.triangles = 20000;
  const gi::Scene scene = gi::make_cliff_scene(o);
  const gi::FlatGeometry geometry = gi::flatten_geometry(scene);
  const gi::FlatInstances flat = gi::flatten_instances(scene, geometry);
  const std::vector<bool> visible = scene.visible_instances();
  gi::bvh::SceneBvh bvh(geometry);
  bvh.update(flat.instances, visible);
  const gi::bvh::EmbreeRayCaster embree(geometry, flat, visible);
  gi::bvh::RaySetOptions ro;
  ro.count = 30000;
  ro.camera = gi::make_gpu_camera(scene.camera, 64, 64);
  const auto rays = gi::bvh::make_ray_set(geometry, flat, visible, ro);
  gi::shader::BvhCpuTracer cpu(bvh);
  int hit_mismatch = 0, occlusion_mismatch = 0, hits = 0;
  double max_rel = 0.0;
  for (const auto& r : rays) {
    gi::shader::Hit h;
    const bool ours = cpu.bvh_trace(r.origin, r.direction, r.tmax, false, h);
    const gi::bvh::CastResult e = embree.closest(r);
    hit_mismatch += ours != e.hit;
    hits += ours;
    if (ours && e.hit) max_rel = std::max(max_rel, double(std::abs(h.t - e.t)) / std::max(h.t, e.t));
    occlusion_mismatch += (!cpu.bvh_trace(r.origin, r.direction, r.tmax, true, h)) != embree.unoccluded(r);
  }
  std::printf("%zu rays, %d hits: hit/miss differ %d, occlusion differs %d, max rel |dt| %.3g\n", rays.size(), hits,
              hit_mismatch, occlusion_mismatch, max_rel);
  EXPECT_GT(hits, int(rays.size() / 4));
  EXPECT_EQ(hit_mismatch, 0);
  EXPECT_EQ(occlusion_mismatch, 0);
  EXPECT_LT(max_rel, 1e-4);
}

// The traversal's two forms (core/shared/bvh_traverse.h: one loop for both
// levels on CPU devices, a loop per level on GPUs) give the same bits: the
// same hit, t, instance, primitive and barycentrics for every ray, closest
// and any-hit, in a scene of many instances (the Cornell box) and one of
// many triangles (the cliff).
TEST(BvhCpuTwin, BothTraversalFormsGiveTheSameBits) {
  gi::CliffOptions cliff;
  cliff.triangles = 20000;
  for (const gi::Scene& scene : {gi::make_cornell_box(), gi::make_cliff_scene(cliff)}) {
    const gi::FlatGeometry geometry = gi::flatten_geometry(scene);
    const gi::FlatInstances flat = gi::flatten_instances(scene, geometry);
    const std::vector<bool> visible = scene.visible_instances();
    gi::bvh::SceneBvh bvh(geometry);
    bvh.update(flat.instances, visible);
    gi::bvh::RaySetOptions ro;
    ro.count = 20000;
    ro.camera = gi::make_gpu_camera(scene.camera, 64, 64);
    const auto rays = gi::bvh::make_ray_set(geometry, flat, visible, ro);
    gi::shader::BvhCpuTracer one_loop(bvh);
    gi::shader::BvhCpuTracerPerLevel per_level(bvh);
    int hits = 0, differ = 0;
    for (const auto& r : rays) {
      for (const bool any_hit : {false, true}) {
        gi::shader::Hit a, b;
        const bool found_a = one_loop.bvh_trace(r.origin, r.direction, r.tmax, any_hit, a);
        const bool found_b = per_level.bvh_trace(r.origin, r.direction, r.tmax, any_hit, b);
        hits += found_a && !any_hit;
        differ += found_a != found_b || std::memcmp(&a.t, &b.t, sizeof a.t) != 0 || a.instance != b.instance ||
                  a.primitive != b.primitive || std::memcmp(&a.barycentrics, &b.barycentrics, sizeof a.barycentrics) != 0;
      }
    }
    EXPECT_GT(hits, int(rays.size() / 4));
    EXPECT_EQ(differ, 0) << "of " << 2 * rays.size() << " traces";
  }
}

}  // namespace
