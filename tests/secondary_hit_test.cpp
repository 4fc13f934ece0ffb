// The GPU's secondary-hit path logic (core/shared/secondary_hit.h, which
// gpu/shaders/hit_radiance.glsl includes) run on the CPU over Embree, held to
// the reference path tracer: where its ending is unbiased, its mean must be
// the radiance the hit reflects, and the path-spread end must fire exactly
// at its threshold.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

#include "core/reference/embree_bridge.h"
#include "core/reference/embree_reference.h"
#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "core/shared/specular.h"

namespace gi::shader {

// Paths end in one cosine-sampled path traced on (unbiased on the Cornell
// box's Lambert walls); glossy hits are followed with Solari's power MIS.
#define HIT_RADIANCE 1
#define HIT_SURFACES_FULL 1
#define HIT_GLOSSY_ROUGHNESS 0.5f
#define HIT_GLOSSY_BOUNCES 8
#define HIT_POWER_MIS 1
#define HIT_ALBEDO_BASE 0
struct TracedEndBridge : EmbreeBridge {
#include "core/shared/secondary_hit.h"
};
#undef HIT_RADIANCE
#undef HIT_SURFACES_FULL
#undef HIT_POWER_MIS

// Bevy's NO_WORLD_CACHE ending: one light sample on the diffuse lobe.
#define HIT_RADIANCE 0
#define HIT_SURFACES_FULL 0
#define HIT_POWER_MIS 0
struct LightSampleEndBridge : EmbreeBridge {
#include "core/shared/secondary_hit.h"
};
#undef HIT_RADIANCE
#undef HIT_ALBEDO_BASE

// The world-cache ending over a cache that returns one irradiance everywhere
// and has one cell size.
#define HIT_RADIANCE 2
#define HIT_ALBEDO_BASE 1
struct UniformCacheBridge : EmbreeBridge {
  vec3 irradiance = vec3(0.0f);
  float cell_size = 1.0f;
#include "core/shared/secondary_hit.h"
  vec3 hit_cache_irradiance(vec3, vec3, float, CacheQuery, uint&) { return irradiance; }
  float hit_cache_cell_size(vec3, uint) { return cell_size; }
};

}  // namespace gi::shader

namespace gi {
namespace {

using shader::EmbreeBridge;
using shader::Hit;
using shader::SurfacePoint;

// The Cornell box with the tall block's material replaced.
struct Box {
  Scene scene;
  FlatGeometry geometry;
  FlatInstances flat;
  std::vector<std::uint8_t> visible;
  std::uint32_t block = 0;

  explicit Box(const Material& block_material) : scene(make_cornell_box()) {
    block = *scene.find_instance("tall_block");
    scene.materials[scene.instances[block].material] = block_material;
    geometry = flatten_geometry(scene);
    flat = flatten_instances(scene, geometry);
    visible = instance_visibility(scene);
  }
};

// One camera ray and the first hit it finds.
struct PrimaryRay {
  glm::vec3 origin, dir;
  Hit hit;
  SurfacePoint s;
  glm::vec3 ng, ns;  // facing the ray
  glm::vec3 emission;
};

// The ray from `origin` through `target`, if it finds `instance` first.
std::optional<PrimaryRay> ray_to(EmbreeBridge& b, glm::vec3 origin, glm::vec3 target, std::uint32_t instance) {
  PrimaryRay r;
  r.origin = origin;
  r.dir = glm::normalize(target - origin);
  if (!b.trace_closest(r.origin, r.dir, shader::RAY_TMAX, r.hit) || r.hit.instance != instance) return std::nullopt;
  r.s = b.surface_at_hit(r.hit);
  const bool front = glm::dot(r.dir, r.s.geometric_normal) < 0.0f;
  r.ng = front ? r.s.geometric_normal : -r.s.geometric_normal;
  r.ns = glm::dot(r.s.shading_normal, r.ng) < 0.0f ? -r.s.shading_normal : r.s.shading_normal;
  r.emission = front ? r.s.emissive : glm::vec3(0.0f);
  return r;
}

SurfacePoint light_centre(EmbreeBridge& b, const Scene& scene) {
  return b.surface_at(*scene.find_instance("light"), 0u, glm::vec2(0.5f));
}

// Rays from just inside the box's open front, high up, at the centres of
// `instance`'s triangles that it sees first and that face the light (so the
// reference has light to compare).
std::vector<PrimaryRay> rays_at(EmbreeBridge& b, const Scene& scene, std::uint32_t instance, std::size_t most) {
  const glm::vec3 origin(0.278f, 0.45f, 0.01f);
  const SurfacePoint light = light_centre(b, scene);
  std::vector<PrimaryRay> rays;
  for (std::uint32_t tri = 0; tri < b.scene_instance(instance).triangle_count && rays.size() < most; ++tri) {
    const std::optional<PrimaryRay> r =
        ray_to(b, origin, b.surface_at(instance, tri, glm::vec2(1.0f / 3.0f)).position, instance);
    if (!r) continue;
    const glm::vec3 to_light = light.position - r->s.position;
    if (glm::dot(r->ng, to_light) <= 0.0f || glm::dot(light.geometric_normal, to_light) >= 0.0f) continue;
    rays.push_back(*r);
  }
  return rays;
}

// Rays at the centres of `instance`'s upward faces whose mirror direction
// meets the light's centre: the glossy path finds the emitter by its bounce
// as often as by NEE, so their MIS weights decide the answer.
std::vector<PrimaryRay> rays_mirroring_the_light(EmbreeBridge& b, const Scene& scene, std::uint32_t instance) {
  const glm::vec3 light = light_centre(b, scene).position;
  std::vector<PrimaryRay> rays;
  for (std::uint32_t tri = 0; tri < b.scene_instance(instance).triangle_count; ++tri) {
    const SurfacePoint p = b.surface_at(instance, tri, glm::vec2(1.0f / 3.0f));
    if (p.geometric_normal.y < 0.99f) continue;
    const glm::vec3 image(light.x, 2.0f * p.position.y - light.y, light.z);  // the light mirrored in the face
    if (const std::optional<PrimaryRay> r = ray_to(b, p.position + 0.5f * (p.position - image), p.position, instance))
      rays.push_back(*r);
  }
  return rays;
}

// Mean and standard error of a luminance estimator over n samples.
struct Estimate {
  double mean = 0.0, error = 0.0;
};

template <class Sample>
Estimate estimate(std::uint32_t n, Sample sample) {
  double sum = 0.0, sum2 = 0.0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double x = shader::luminance(sample(i));
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / n)};
}

// The two estimates agree within 4 combined standard errors.
void expect_agree(const Estimate& a, const Estimate& b, const char* what) {
  const double tolerance = 4.0 * std::hypot(a.error, b.error);
  EXPECT_LE(std::abs(a.mean - b.mean), tolerance)
      << what << ": " << a.mean << " ± " << a.error << " vs the path tracer's " << b.mean << " ± " << b.error;
  EXPECT_GT(b.mean, 10.0 * b.error) << what << ": the reference sees too little light to judge";
}

std::uint32_t seed(std::uint32_t ray, std::uint32_t domain, std::uint32_t sample) {
  return shader::rng_seed(7u, domain, ray, sample);
}

// The reflected radiance at the ray's hit by the reference path tracer: the
// camera ray's radiance less the hit's own emission.
Estimate reference_reflected(EmbreeBridge& b, const PrimaryRay& r, std::uint32_t index, std::uint32_t n) {
  return estimate(n, [&](std::uint32_t i) {
    std::uint32_t rng = seed(index, 1u, i);
    return b.path_trace(r.origin, r.dir, rng, 32u) - r.emission;
  });
}

template <class Bridge>
Estimate secondary(Bridge& b, const PrimaryRay& r, std::uint32_t index, std::uint32_t n) {
  return estimate(n, [&](std::uint32_t i) {
    std::uint32_t rng = seed(index, 2u, i);
    return b.secondary_hit_radiance(r.hit, r.s, r.ng, r.ns, r.dir, typename Bridge::CacheQuery{}, rng);
  });
}

Material metal(float perceptual_roughness) {
  Material m;
  m.name = "metal";
  m.base_color = glm::vec3(0.9f, 0.8f, 0.6f);
  m.metallic = 1.0f;
  m.perceptual_roughness = perceptual_roughness;
  return m;
}

// A Lambert surface (the Cornell walls): the path ends at once in a traced
// cosine path; its mean is the reflected radiance.
TEST(SecondaryHit, TracedEndOnLambertWallsIsTheReflectedRadiance) {
  const Box box(metal(0.0f));
  const EmbreeScene embree(box.geometry, box.flat, box.visible);
  shader::TracedEndBridge b{EmbreeBridge::over(box.geometry, box.flat, embree.scene())};
  std::uint32_t index = 0;
  for (const char* wall : {"floor_ceiling_back", "red_wall", "green_wall", "short_block"}) {
    for (const PrimaryRay& r : rays_at(b, box.scene, *box.scene.find_instance(wall), 2)) {
      SCOPED_TRACE(wall);
      expect_agree(secondary(b, r, index, 6000), reference_reflected(b, r, index, 6000), wall);
      ++index;
    }
  }
  EXPECT_GE(index, 6u);
}

// A glossy or mirror metal block: the path follows it along its BRDF (NEE
// and the bounce weighted by the power heuristic, no NEE on the mirror) to
// the Lambert walls or the light. Unbiased, so again the reflected radiance.
TEST(SecondaryHit, GlossyPathThroughMetalIsTheReflectedRadiance) {
  for (const float roughness : {0.0f, 0.3f}) {
    SCOPED_TRACE(roughness);
    const Box box(metal(roughness));
    const EmbreeScene embree(box.geometry, box.flat, box.visible);
    shader::TracedEndBridge b{EmbreeBridge::over(box.geometry, box.flat, embree.scene())};
    std::vector<PrimaryRay> rays = rays_at(b, box.scene, box.block, 4);
    const std::vector<PrimaryRay> mirroring = rays_mirroring_the_light(b, box.scene, box.block);
    ASSERT_GE(rays.size(), 2u);
    ASSERT_GE(mirroring.size(), 1u);
    rays.insert(rays.end(), mirroring.begin(), mirroring.end());
    for (std::uint32_t i = 0; i < rays.size(); ++i)
      expect_agree(secondary(b, rays[i], i, 6000), reference_reflected(b, rays[i], i, 6000), "block");
  }
}

// One light sample at a Lambert hit: the direct light it reflects, which is
// the direct-lighting reference's radiance less the emission.
TEST(SecondaryHit, LightSampleEndIsTheReflectedDirectLight) {
  const Box box(metal(0.0f));
  const EmbreeScene embree(box.geometry, box.flat, box.visible);
  shader::LightSampleEndBridge b{EmbreeBridge::over(box.geometry, box.flat, embree.scene())};
  std::uint32_t index = 0;
  for (const char* wall : {"floor_ceiling_back", "red_wall", "short_block"}) {
    for (const PrimaryRay& r : rays_at(b, box.scene, *box.scene.find_instance(wall), 2)) {
      const Estimate direct = estimate(6000, [&](std::uint32_t i) {
        std::uint32_t rng = seed(index, 1u, i);
        return b.direct_trace(r.origin, r.dir, rng) - r.emission;
      });
      expect_agree(secondary(b, r, index, 6000), direct, wall);
      ++index;
    }
  }
  EXPECT_GE(index, 4u);
}

// Solari 0.18's path-spread end: the footprint after the first hit,
// spread² = t² / (pdf · cos θ_o), ends the path there exactly when it
// exceeds a0 · the cell size. Ending there returns base_color/π · E of the
// cache; one step past the threshold the path goes on.
TEST(SecondaryHit, PathSpreadEndsAtItsThreshold) {
  const Box box(metal(0.3f));
  const EmbreeScene embree(box.geometry, box.flat, box.visible);
  shader::UniformCacheBridge b{EmbreeBridge::over(box.geometry, box.flat, embree.scene())};
  b.irradiance = glm::vec3(2.0f, 3.0f, 5.0f);
  b.cell_size = 0.25f;
  const std::vector<PrimaryRay> rays = rays_at(b, box.scene, box.block, 1);
  ASSERT_EQ(rays.size(), 1u);
  const PrimaryRay& r = rays[0];
  const float first_pdf = 0.5f;
  const float spread2 = r.hit.t * r.hit.t / (first_pdf * glm::max(glm::dot(r.ns, -r.dir), 1e-6f));
  const glm::vec3 cached = metal(0.3f).base_color * shader::INV_PI * b.irradiance;
  auto radiance = [&](float a0) {
    std::uint32_t rng = seed(0u, 3u, 0u);
    return b.glossy_path_radiance(r.hit, r.dir, shader::UniformCacheBridge::CacheQuery{},
                                  b.glossy_path_end(a0, first_pdf, 0.0f), rng);
  };
  const glm::vec3 ends = radiance(spread2 / b.cell_size * 0.999f);
  EXPECT_NEAR(ends.x, cached.x, 1e-5f * cached.x);
  EXPECT_NEAR(ends.y, cached.y, 1e-5f * cached.y);
  EXPECT_NEAR(ends.z, cached.z, 1e-5f * cached.z);
  const glm::vec3 goes_on = radiance(spread2 / b.cell_size * 1.001f);
  EXPECT_GT(glm::length(goes_on - cached), 1e-3f * glm::length(cached)) << "the path ended below the threshold";
  // A negative a0 keeps the roughness rule: this glossy hit (alpha 0.09) is followed.
  EXPECT_GT(glm::length(radiance(-1.0f) - cached), 1e-3f * glm::length(cached));
}

// Solari 0.19's end (v0.19.0 realtime/specular_gi.wgsl:131-139): at a hit
// reached by a ray longer than √3 cells, once the path's summed alpha is
// above HIT_GLOSSY_ROUGHNESS (0.5 in these tests, 0.4 in Solari); either condition short of its
// threshold and the path goes on.
TEST(SecondaryHit, LongRayRoughPathEndsOnlyWhenBothHold) {
  const Box box(metal(0.3f));
  const EmbreeScene embree(box.geometry, box.flat, box.visible);
  shader::UniformCacheBridge b{EmbreeBridge::over(box.geometry, box.flat, embree.scene())};
  b.irradiance = glm::vec3(2.0f, 3.0f, 5.0f);
  const std::vector<PrimaryRay> rays = rays_at(b, box.scene, box.block, 1);
  ASSERT_EQ(rays.size(), 1u);
  const PrimaryRay& r = rays[0];
  const glm::vec3 cached = metal(0.3f).base_color * shader::INV_PI * b.irradiance;
  auto radiance = [&](float cell_size, float path_roughness) {
    b.cell_size = cell_size;
    std::uint32_t rng = seed(0u, 4u, 0u);
    auto end = b.glossy_path_end(-1.0f, 0.0f, 0.0f);
    end.path_roughness = path_roughness;
    return b.glossy_path_radiance(r.hit, r.dir, shader::UniformCacheBridge::CacheQuery{}, end, rng);
  };
  auto ended = [&](const glm::vec3& v) { return glm::length(v - cached) <= 1e-5f * glm::length(cached); };
  const float long_cell = r.hit.t / std::sqrt(3.0f) * 0.99f, short_cell = r.hit.t / std::sqrt(3.0f) * 1.01f;
  EXPECT_TRUE(ended(radiance(long_cell, 0.51f)));
  EXPECT_FALSE(ended(radiance(long_cell, 0.49f))) << "summed alpha below the threshold must not end the path";
  EXPECT_FALSE(ended(radiance(short_cell, 0.51f))) << "a ray shorter than sqrt(3) cells must not end the path";
}

}  // namespace
}  // namespace gi
