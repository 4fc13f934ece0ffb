// The world cache: its shared maths on the CPU (the code the shaders run), its
// bias against Embree irradiance on the Cornell box, and the bit-identity of
// its cells across runs and lavapipe thread counts.
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "core/reference/embree_irradiance.h"
#include "core/reference/embree_reference.h"
#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "core/shared/world_cache.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "gpu/realtime_settings.h"
#include "replay/run_scenario.h"
#include "core/profile.h"
#include "tests/cornell_cache_view.h"
#include "tests/test_support.h"

namespace gi {
namespace {

using namespace gi::shader;

TEST(WorldCacheMaths, CellSizeDoublesWithDistanceOverLodScale) {
  const vec3 eye(0.0f);
  // 0.18: base 0.25, lod_scale 8: 2^floor(log2(1 + d/8)).
  EXPECT_EQ(world_cache_cell_size(vec3(0, 0, 1), eye, 0.25f, 8.0f), 0.25f);   // 1 + 1/8 → lod 1
  EXPECT_EQ(world_cache_cell_size(vec3(0, 0, 8), eye, 0.25f, 8.0f), 0.5f);    // 1 + 1 = 2 → lod 2
  EXPECT_EQ(world_cache_cell_size(vec3(0, 0, 24), eye, 0.25f, 8.0f), 1.0f);   // 1 + 3 = 4
  EXPECT_EQ(world_cache_cell_size(vec3(0, 0, 23), eye, 0.25f, 8.0f), 0.5f);   // just below 4
  // 0.17's lod_scale 30 keeps fine cells four times further out.
  EXPECT_EQ(world_cache_cell_size(vec3(0, 0, 24), eye, 0.25f, 30.0f), 0.25f);
}

TEST(WorldCacheMaths, ChecksumNeverEmptyAndKeysStayInTheTable) {
  std::set<uint> keys;
  for (int i = 0; i < 2000; ++i) {
    const vec3 p(0.37f * float(i), -1.1f * float(i % 7), 0.05f * float(i % 13));
    const uvec3 qp = world_cache_quantize_position(p, 0.25f);
    const uvec3 qn = world_cache_quantize_normal(normalize(vec3(0.2f, 1.0f, -0.1f)), 1.0f);
    EXPECT_NE(world_cache_checksum(qp, qn), WORLD_CACHE_EMPTY_CELL);
    const uint k = world_cache_key(qp, qn, 1u << 16);
    EXPECT_LT(k, 1u << 16);
    keys.insert(k);
    EXPECT_LT(world_cache_next_key(k, 1u << 16, true), 1u << 16);
    EXPECT_LT(world_cache_next_key(k, 1u << 16, false), 1u << 16);
  }
  EXPECT_GT(keys.size(), 1900u);  // distinct points spread over the table
  // Linear probing steps to the next slot and wraps.
  EXPECT_EQ(world_cache_next_key(5u, 16u, true), 6u);
  EXPECT_EQ(world_cache_next_key(15u, 16u, true), 0u);
  // iqint_hash as Bevy's: (n << 13) ^ n, then n · (n² · 15731 + 789221) + 1376312589.
  EXPECT_EQ(iqint_hash(0u), 1376312589u);
}

TEST(WorldCacheMaths, LifetimeRules) {
  // Pixel-rooted: full lifetime. Cache-to-cache: the querier's life (0.18) or the full lifetime (0.17).
  EXPECT_EQ(world_cache_query_life(true, 3u, 30u, false), 30u);
  EXPECT_EQ(world_cache_query_life(false, 3u, 30u, false), 3u);
  EXPECT_EQ(world_cache_query_life(false, 3u, 30u, true), 30u);
  EXPECT_EQ(world_cache_decayed_life(1u), 0u);
  EXPECT_EQ(world_cache_decayed_life(0u), 0u);
  EXPECT_TRUE(world_cache_age_ok(40u, 9u, 30u));   // 31 = lifetime + 1
  EXPECT_FALSE(world_cache_age_ok(41u, 9u, 30u));
}

TEST(WorldCacheMaths, FixedBlendLagsAdaptiveBlendFollows) {
  // A cell at its cap (20 samples, 0.17) whose light goes out: it keeps 19/20 a frame.
  vec4 fixed_cell(1.0f, 1.0f, 1.0f, 20.0f);
  for (int i = 0; i < 20; ++i) fixed_cell = world_cache_blend_fixed(fixed_cell, vec3(0.0f), 20.0f).radiance;
  EXPECT_NEAR(fixed_cell.x, std::pow(0.95f, 20.0f), 1e-5f);  // 36 % left
  // 0.18 at its cap of 32: the luminance delta builds up and the sample cap falls towards 1.
  vec4 cell(1.0f, 1.0f, 1.0f, 32.0f);
  float delta = 0.0f;
  for (int i = 0; i < 20; ++i) {
    WorldCacheBlend b = world_cache_blend_adaptive(cell, delta, vec3(0.0f), 32.0f, 0.125f, 0.125f);
    cell = b.radiance;
    delta = b.luminance_delta;
  }
  // 8.4 % left after 20 frames (the delta needs a few frames to build up), and
  // the cap reaches 1 soon after: exactly 0 by frame 25.
  EXPECT_LT(cell.x, 0.1f);
  EXPECT_GT(cell.x, 0.05f);
  // Static light: no delta, the adaptive cap stays at 32 and a new sample moves the mean by 1/32.
  const WorldCacheBlend still = world_cache_blend_adaptive(vec4(1, 1, 1, 32), 0.0f, vec3(2.0f), 32.0f, 0.125f, 0.125f);
  EXPECT_NEAR(still.radiance.x, 1.0f + 1.0f / 32.0f, 1e-6f);
}

struct CacheBias {
  double energy_ratio;   // Σ cache / Σ Embree over the points
  double normalised_mae; // Σ |cache − Embree| / Σ Embree
  std::size_t points;
};

// Cache irradiance at the Cornell box's primary surfaces against Embree
// irradiance at the same points (core/reference/embree_irradiance.h), with
// cells of `cell_size_base` metres (0.18: 0.25).
CacheBias cornell_cache_bias(float cell_size_base) {
  const std::uint32_t w = 64, h = 64;
  gpu::WorldCacheSettings cache = world_cache_settings_from_profile(load_profile("solari-0.18"));
  cache.cells = 1u << 16;
  cache.cell_size_base = cell_size_base;
  test::CornellCacheView view(w, h, cache);  // the cache view is what this test reads
  gpu::Renderer& renderer = view.renderer();
  const Scene& scene = view.scene();
  // 64 frames to converge (multi-bounce builds up one bounce a frame), then
  // the cache view averaged over 32 more to take the per-frame noise out.
  std::vector<glm::dvec3> sum(std::size_t(w) * h, glm::dvec3(0.0));
  const std::uint32_t warm = 64, averaged = 32;
  for (std::uint32_t f = 0; f < warm + averaged; ++f) {
    view.render(f);
    if (f < warm) continue;
    const Image v = renderer.cache_view();
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += glm::dvec3(v.pixels[i]);
  }
  // Points: every 4th pixel of every 4th row that sees a non-emissive surface.
  const Image position = renderer.gbuffer_layer("position");
  const Image normal = renderer.gbuffer_layer("geometric_normal");
  const Image depth = renderer.gbuffer_layer("depth");
  const Image emissive = renderer.gbuffer_layer("emissive");
  std::vector<IrradiancePoint> points;
  std::vector<glm::dvec3> cache_e;
  const GpuCamera cam = make_gpu_camera(scene.camera, w, h);
  for (std::uint32_t y = 2; y < h; y += 4)
    for (std::uint32_t x = 2; x < w; x += 4) {
      const std::size_t i = std::size_t(y) * w + x;
      if (depth.pixels[i].x <= 0.0f || glm::length(emissive.pixels[i]) > 0.0f) continue;
      glm::vec3 n = normal.pixels[i];
      if (glm::dot(n, glm::vec3(cam.position) - position.pixels[i]) < 0.0f) n = -n;
      points.push_back({position.pixels[i], n});
      cache_e.push_back(sum[i] / double(averaged));
    }
  IrradianceOptions io;
  io.samples = 512;
  const std::vector<glm::vec3> ref =
      embree_irradiance(view.geometry(), view.flat(), instance_visibility(scene), points, io);
  double lum_cache = 0.0, lum_ref = 0.0, abs_err = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double a = luminance(glm::vec3(cache_e[i])), b = luminance(ref[i]);
    lum_cache += a;
    lum_ref += b;
    abs_err += std::abs(a - b);
  }
  return {lum_cache / lum_ref, abs_err / lum_ref, points.size()};
}

TEST(WorldCacheGpu, CornellIrradianceBiasAgainstEmbree) {
  const CacheBias coarse = cornell_cache_bias(0.25f), fine = cornell_cache_bias(0.0625f);
  std::cout << "world cache vs Embree irradiance on the Cornell box (" << coarse.points
            << " points): 0.25 m cells: energy ratio " << coarse.energy_ratio << ", normalised mean |error| "
            << coarse.normalised_mae << "; 0.0625 m cells: " << fine.energy_ratio << ", " << fine.normalised_mae
            << "\n";
  ASSERT_GT(coarse.points, 150u);
  // Measured (lavapipe, 2026-12-02; the runs are bit-identical): energy
  // 1.021 with 0.25 m cells, 0.953 with 0.0625 m; normalised mean |error|
  // 0.552 and 0.253. Bounds a little outside those, so a regression of a few
  // per cent fails. Pointwise, a 0.25 m cell (a Cornell wall is about 2 × 2
  // of them) holds one irradiance for lit and shadowed parts alike, measured
  // at the cell's first query point: the error is the quantisation's, and it
  // must halve with cells a quarter the size.
  EXPECT_NEAR(coarse.energy_ratio, 1.0, 0.05);
  EXPECT_NEAR(fine.energy_ratio, 1.0, 0.06);
  EXPECT_LT(coarse.normalised_mae, 0.60);
  EXPECT_LT(fine.normalised_mae, 0.5 * coarse.normalised_mae);
}

// Life, checksum and radiance (and root frame) buffers bit-identical across
// two runs and across LP_NUM_THREADS=1 and the default.
TEST(WorldCacheGpu, CellsBitIdenticalAcrossRunsAndThreadCounts) {
  test::TempDir dir("world_cache_determinism");
  const std::string scenario = (test::source_dir() / "scenarios/cache_light_toggle_closed_room.json").string();
  auto run = [&](const std::string& name, const std::string& env) {
    const test::CommandResult r = test::run_giharness(
        "run " + scenario + " --frames 12 --set world_cache.cells=65536 --out " + (dir.path() / name).string(), env);
    // 12 frames end before the light toggle: blend_lag judges nothing
    // (inconclusive, so exit 1) while finite and cache_lifetime pass; the
    // cells are what is compared.
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_EQ(test::check_result(dir.path() / name, "finite").value("verdict", ""), "pass") << name;
    EXPECT_EQ(test::check_result(dir.path() / name, "cache_lifetime").value("verdict", ""), "pass") << name;
    EXPECT_EQ(test::check_result(dir.path() / name, "blend_lag").value("verdict", ""), "inconclusive") << name;
    return test::read_json(dir.path() / name / "summary.json")["world_cache_hashes"];
  };
  const nlohmann::json a = run("a", "");
  ASSERT_TRUE(a.is_object());
  EXPECT_EQ(a, run("b", ""));
  EXPECT_EQ(a, run("one_thread", "LP_NUM_THREADS=1"));
}

}  // namespace
}  // namespace gi
