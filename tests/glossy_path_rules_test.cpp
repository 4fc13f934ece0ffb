// Solari's glossy-path rules (core/shared/secondary_hit.h) on the CPU over
// Embree: which vertex counts as a perfect mirror (specular.perfect_mirror)
// how the sun reaches the path (specular.directional_lights) and 0.19's
// mirror-vertex throughput (specular.mirror_throughput), each shown changing
// what it claims and nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/reference/embree_bridge.h"
#include "core/reference/embree_reference.h"
#include "core/scene_flatten.h"
#include "core/scenes/mesh_builder.h"
#include "core/shared/specular.h"

namespace gi::shader {

// Paths follow every hit (no rough ending in this scene's one floor).
#define HIT_RADIANCE 1
#define HIT_SURFACES_FULL 1
#define HIT_GLOSSY_ROUGHNESS 0.5f
#define HIT_GLOSSY_BOUNCES 8
#define HIT_POWER_MIS 1
#define HIT_ALBEDO_BASE 0
// Bevy's rules (0.18, 0.19).
#define HIT_PERFECT_MIRROR_METAL 1
#define HIT_SUN_NEE_ONLY 1
struct BevyRules : EmbreeBridge {
#include "core/shared/secondary_hit.h"
};
#undef HIT_PERFECT_MIRROR_METAL
#undef HIT_SUN_NEE_ONLY
// The harness's earlier rules: alpha alone makes a mirror, the sun by MIS.
#define HIT_PERFECT_MIRROR_METAL 0
#define HIT_SUN_NEE_ONLY 0
struct HarnessRules : EmbreeBridge {
#include "core/shared/secondary_hit.h"
};
#undef HIT_PERFECT_MIRROR_METAL
#undef HIT_SUN_NEE_ONLY
// Alpha alone makes a mirror, the sun by NEE alone.
#define HIT_PERFECT_MIRROR_METAL 0
#define HIT_SUN_NEE_ONLY 1
struct AlphaMirrorSunNee : EmbreeBridge {
#include "core/shared/secondary_hit.h"
};
#undef HIT_PERFECT_MIRROR_METAL
#undef HIT_SUN_NEE_ONLY
// Bevy 0.19's mirror-vertex throughput (specular.mirror_throughput full_brdf).
#define HIT_PERFECT_MIRROR_METAL 1
#define HIT_SUN_NEE_ONLY 1
#undef HIT_MIRROR_THROUGHPUT_BRDF  // secondary_hit.h's default, 0, from the first include
#define HIT_MIRROR_THROUGHPUT_BRDF 1
struct Bevy019MirrorThroughput : EmbreeBridge {
#include "core/shared/secondary_hit.h"
};

}  // namespace gi::shader

namespace gi {
namespace {

using shader::EmbreeBridge;

const glm::vec3 kSun = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f));  // towards the light

// A 20 m floor of one material at y = 0 under the sun, and nothing else.
struct SunlitFloor {
  Scene scene;
  FlatGeometry geometry;
  FlatInstances flat;
  std::vector<std::uint8_t> visible;

  explicit SunlitFloor(const Material& floor) {
    Mesh mesh;
    mesh.name = "floor";
    add_quad(mesh, {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, {0, 1, 0});
    add_object(scene, mesh, floor);
    DirectionalLight sun;
    sun.name = "sun";
    sun.direction = kSun;
    sun.illuminance = 1.0f;
    scene.directional_lights.push_back(sun);
    geometry = flatten_geometry(scene);
    flat = flatten_instances(scene, geometry);
    visible = instance_visibility(scene);
  }
};

// The glossy path from a point 1 m above the floor along `dir`: the mean
// luminance over n samples, and how many samples saw any light.
template <class Bridge>
std::pair<double, std::uint32_t> glossy_mean(const SunlitFloor& f, glm::vec3 dir, std::uint32_t n) {
  const EmbreeScene embree(f.geometry, f.flat, f.visible);
  Bridge b{EmbreeBridge::over(f.geometry, f.flat, embree.scene())};
  double sum = 0.0;
  std::uint32_t lit = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t rng = shader::rng_seed(3u, 5u, 0u, i);
    const glm::vec3 l = b.glossy_path_radiance_from(true, shader::Hit{}, glm::vec3(0, 1, 0), dir,
                                                    typename Bridge::CacheQuery{},
                                                    b.glossy_path_end(-1.0f, 1e30f, 0.0f), rng);
    const double y = shader::luminance(l);
    sum += y;
    lit += y > 0.0 ? 1u : 0u;
  }
  return {sum / n, lit};
}

Material smooth(float metallic) {
  Material m;
  m.name = metallic > 0.5f ? "smooth_metal" : "smooth_dielectric";
  m.base_color = glm::vec3(0.8f);
  m.metallic = metallic;
  m.perceptual_roughness = 0.0f;  // alpha 0.001 after the clamp: a mirror by alpha
  return m;
}

// A mirror in the sun's mirror direction: Bevy's escape rule adds nothing
// (the sun reaches a glossy path by NEE alone, and a mirror vertex has none),
// the harness's earlier rule shows the sun's disc, about its radiance of
// 1 lux over the 0.27° cone's solid angle (some 14 700).
TEST(GlossyPathRules, NoSunDiscInAMirrorUnderBevysEscapeRule) {
  const SunlitFloor f(smooth(1.0f));
  const glm::vec3 towards_mirror_image(kSun.x, -kSun.y, kSun.z);
  const auto [bevy, bevy_lit] = glossy_mean<shader::BevyRules>(f, towards_mirror_image, 256);
  const auto [harness, harness_lit] = glossy_mean<shader::HarnessRules>(f, towards_mirror_image, 256);
  EXPECT_EQ(bevy, 0.0);
  EXPECT_EQ(bevy_lit, 0u);
  EXPECT_GT(harness, 1000.0);
  EXPECT_GT(harness_lit, 200u);
}

// A smooth dielectric is no perfect mirror in Bevy: its vertex runs NEE, so
// the sun lights its diffuse lobe in every sample; with alpha alone making a
// mirror (and the sun by NEE alone) the path sees no light at all. A smooth
// metal is a mirror under both rules: the same path, bit for bit.
TEST(GlossyPathRules, ASmoothDielectricRunsNeeUnderBevysMirrorRule) {
  const glm::vec3 dir = glm::normalize(glm::vec3(-0.6f, -1.0f, 0.1f));  // not the sun's mirror direction
  const SunlitFloor dielectric(smooth(0.0f));
  const auto [bevy, bevy_lit] = glossy_mean<shader::BevyRules>(dielectric, dir, 256);
  const auto [alpha, alpha_lit] = glossy_mean<shader::AlphaMirrorSunNee>(dielectric, dir, 256);
  // The diffuse lobe under the sun: about base (1 - F) / pi * E * cos, cos = kSun.y.
  const double lambert = 0.8 * 0.96 / M_PI * kSun.y;
  EXPECT_EQ(bevy_lit, 256u);
  EXPECT_NEAR(bevy, lambert, 0.1 * lambert);
  EXPECT_EQ(alpha, 0.0);
  EXPECT_EQ(alpha_lit, 0u);

  const SunlitFloor metal(smooth(1.0f));
  EXPECT_EQ(glossy_mean<shader::BevyRules>(metal, dir, 64), glossy_mean<shader::AlphaMirrorSunNee>(metal, dir, 64));
}

// A glossy metal under the sun: with the sun's NEE at weight 1 and nothing
// from escaped bounces the path is unbiased, its mean the reference path
// tracer's (which weighs the two by the balance heuristic).
TEST(GlossyPathRules, SunByNeeAloneKeepsAGlossyPathUnbiased) {
  Material glossy = metal_material("glossy", glm::vec3(0.9f, 0.8f, 0.6f), 0.4f);
  const SunlitFloor f(glossy);
  const glm::vec3 dir = glm::normalize(glm::vec3(-kSun.x, -kSun.y, -kSun.z) + glm::vec3(0.2f, 0.0f, 0.0f));
  const std::uint32_t n = 20000;
  const EmbreeScene embree(f.geometry, f.flat, f.visible);
  shader::BevyRules b{EmbreeBridge::over(f.geometry, f.flat, embree.scene())};
  double sum = 0.0, sum2 = 0.0, ref = 0.0, ref2 = 0.0;
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t rng = shader::rng_seed(4u, 6u, 0u, i);
    const double y = shader::luminance(b.glossy_path_radiance_from(
        true, shader::Hit{}, glm::vec3(0, 1, 0), dir, shader::BevyRules::CacheQuery{},
        b.glossy_path_end(-1.0f, 1e30f, 0.0f), rng));
    sum += y;
    sum2 += y * y;
    std::uint32_t rng2 = shader::rng_seed(4u, 7u, 0u, i);
    const double r = shader::luminance(b.path_trace(glm::vec3(0, 1, 0), dir, rng2, 8u));
    ref += r;
    ref2 += r * r;
  }
  const double m = sum / n, mr = ref / n;
  const double se = std::sqrt((sum2 / n - m * m) / n + (ref2 / n - mr * mr) / n);
  EXPECT_GT(mr, 20.0 * se) << "too little light to judge";
  EXPECT_NEAR(m, mr, 4.0 * se) << "glossy path " << m << ", reference " << mr;
}

// A smooth floor under a 6 m emissive ceiling (radiance 1, black, rough,
// 2 m up, the scene's only light; the path's reflection meets it at
// (-1.5, 2, 0.6)), 0.19's layered model.
struct LitCeiling {
  Scene scene;
  FlatGeometry geometry;
  FlatInstances flat;
  std::vector<std::uint8_t> visible;

  explicit LitCeiling(const Material& floor) {
    scene.brdf_model = shader::BRDF_LAYERED;
    Mesh mesh;
    mesh.name = "floor";
    add_quad(mesh, {-10, 0, -10}, {10, 0, -10}, {10, 0, 10}, {-10, 0, 10}, {0, 1, 0});
    add_object(scene, mesh, floor);
    Mesh ceiling_mesh;
    ceiling_mesh.name = "ceiling";
    add_quad(ceiling_mesh, {-3, 2, -3}, {3, 2, -3}, {3, 2, 3}, {-3, 2, 3}, {0, 0, 0});
    Material ceiling;
    ceiling.name = "ceiling";
    ceiling.base_color = glm::vec3(0.0f);
    ceiling.perceptual_roughness = 1.0f;
    ceiling.emissive = glm::vec3(1.0f);
    add_object(scene, ceiling_mesh, ceiling);
    geometry = flatten_geometry(scene);
    flat = flatten_instances(scene, geometry);
    visible = instance_visibility(scene);
  }
};

// Mean and standard error of the glossy path's luminance from 1 m above the
// floor along dir (glossy == false: the reference path tracer's).
template <class Bridge>
std::pair<double, double> path_mean(const LitCeiling& f, glm::vec3 dir, bool glossy, std::uint32_t n) {
  const EmbreeScene embree(f.geometry, f.flat, f.visible);
  Bridge b{EmbreeBridge::over(f.geometry, f.flat, embree.scene())};
  double sum = 0.0, sum2 = 0.0;
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t rng = shader::rng_seed(5u, glossy ? 8u : 9u, 0u, i);
    const glm::vec3 l = glossy ? b.glossy_path_radiance_from(true, shader::Hit{}, glm::vec3(0, 1, 0), dir,
                                                             typename Bridge::CacheQuery{},
                                                             b.glossy_path_end(-1.0f, 1e30f, 0.0f), rng)
                               : b.path_trace(glm::vec3(0, 1, 0), dir, rng, 8u);
    const double y = shader::luminance(l);
    sum += y;
    sum2 += y * y;
  }
  const double m = sum / n;
  return {m, std::sqrt(std::max(sum2 / n - m * m, 0.0) / n)};
}

// Bevy 0.19 multiplies a glossy path's throughput at an alpha <= 0.001 vertex
// by the whole BRDF without a pdf (v0.19.0 realtime/specular_gi.wgsl:156-159):
// a smooth dielectric seen in a mirror reflects the ceiling with F plus its
// diffuse lobe at the reflection, diffuse·layering·NdotL (scene/brdf.wgsl:
// 84-86) = 0.8/π·(1 − F(c))²·c with c = n·v = n·l and F Schlick's with
// F0 = 0.04, f90 = 1 — over the path tracer by that much, its diffuse light
// (NEE at weight 1) otherwise right. The sampled rule is the path tracer's
// within noise. A smooth metal has no diffuse lobe: both rules agree.
// Error rate: each 4-sigma bound on a mean of 20 000 paths fails by chance
// with probability about 6e-5 (fixed seeds: the figures are reproducible).
TEST(GlossyPathRules, Bevy019MirrorThroughputOverReflectsASmoothDielectricByItsDiffuseLobe) {
  const glm::vec3 dir = glm::normalize(glm::vec3(-0.5f, -1.0f, 0.2f));
  const std::uint32_t n = 20000;
  const LitCeiling dielectric(smooth(0.0f));
  const auto [full, full_se] = path_mean<shader::Bevy019MirrorThroughput>(dielectric, dir, true, n);
  const auto [sampled, sampled_se] = path_mean<shader::BevyRules>(dielectric, dir, true, n);
  const auto [ref, ref_se] = path_mean<shader::BevyRules>(dielectric, dir, false, n);
  const double c = -dir.y;
  const double fresnel = 0.04 + 0.96 * std::pow(1.0 - c, 5.0);
  const double predicted = 0.8 / M_PI * (1.0 - fresnel) * (1.0 - fresnel) * c;
  EXPECT_GT(ref, 20.0 * ref_se) << "too little light to judge";
  EXPECT_NEAR(sampled, ref, 4.0 * std::hypot(sampled_se, ref_se)) << "sampled " << sampled << ", reference " << ref;
  EXPECT_NEAR(full - ref, predicted, 4.0 * std::hypot(full_se, ref_se))
      << "0.19's rule " << full << ", reference " << ref << ", predicted excess " << predicted;

  const LitCeiling metal(smooth(1.0f));
  const auto [metal_full, metal_full_se] = path_mean<shader::Bevy019MirrorThroughput>(metal, dir, true, 256);
  const auto [metal_sampled, metal_sampled_se] = path_mean<shader::BevyRules>(metal, dir, true, 256);
  EXPECT_GT(metal_sampled, 0.5);  // F0 = 0.8: the ceiling in the mirror
  EXPECT_NEAR(metal_full, metal_sampled, 0.005 * metal_sampled + 4.0 * std::hypot(metal_full_se, metal_sampled_se));
}

}  // namespace
}  // namespace gi
