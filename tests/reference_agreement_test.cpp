// The walking skeleton's proof: two independent estimators of the same image —
// the GPU reference mode (test_backend(): ray queries on lavapipe, the bvh
// backend on devices without them) and the Embree path tracer — agree within
// their combined noise, and the comparison is sharp enough to reject a 5%
// albedo change in one of them.
#include <gtest/gtest.h>

#include "core/gltf_import.h"
#include "core/metrics.h"
#include "core/reference/embree_reference.h"
#include "core/scenes/cornell_box.h"
#include "tests/test_support.h"

namespace gi {
namespace {

constexpr std::uint32_t kSize = 64;
constexpr std::uint32_t kGpuFrames = 256;  // one sample per frame, accumulated
constexpr std::uint32_t kEmbreeSpp = 1024;
constexpr double kNoiseFactor = 3.0;       // relMSE ≤ 3 × combined noise
constexpr double kEnergyTolerance = 0.01;  // energy within 1%

ReferenceResult embree(const Scene& scene) {
  ReferenceOptions o;
  o.width = o.height = kSize;
  o.spp = kEmbreeSpp;
  o.seed = 7;
  return render_reference(scene, o);
}

Comparison gpu_vs_embree(const Scene& gpu_scene, const Scene& embree_scene) {
  const test::GpuReference g = test::render_gpu_reference(gpu_scene, kSize, kSize, kGpuFrames, 1, 7);
  EXPECT_EQ(g.nonfinite_samples, 0u);
  const ReferenceResult e = embree(embree_scene);
  EXPECT_EQ(e.nonfinite_samples, 0u);
  const Comparison c = compare(g.mean, g.half_a, g.half_b, e.mean, e.half_a, e.half_b);
  std::printf("relMSE %.3e, noise gpu %.3e + embree %.3e = %.3e (x%.2f), energy ratio %.5f (sigma %.5f)\n", c.relmse,
              c.noise_x, c.noise_y, c.combined_noise, c.relmse_over_noise, c.energy_ratio, c.energy_ratio_sigma);
  return c;
}

void expect_agreement(const Comparison& c) {
  const ComparisonVerdict v = c.judge(kNoiseFactor, kEnergyTolerance);
  EXPECT_TRUE(v.passed) << v.reason;
  EXPECT_LE(c.relmse, kNoiseFactor * c.combined_noise);
  EXPECT_NEAR(c.energy_ratio, 1.0, kEnergyTolerance);
  // The test is only meaningful when the energy noise is well below 1%.
  EXPECT_LT(3.0 * c.energy_ratio_sigma, kEnergyTolerance);
}

Scene scaled_albedo(Scene s, float k) {
  for (Material& m : s.materials) m.base_color *= k;
  return s;
}

TEST(ReferenceAgreement, CornellBoxGpuMatchesEmbree) {
  const Scene scene = make_cornell_box();
  expect_agreement(gpu_vs_embree(scene, scene));
}

TEST(ReferenceAgreement, GlossyGltfSceneGpuMatchesEmbree) {
  const Scene scene = import_gltf(test::source_dir() / "scenarios/assets/glossy_room.gltf");
  // The scene must hold what this test claims to cover.
  bool rough_dielectric = false, glossy_metal = false;
  for (const Material& m : scene.materials) {
    rough_dielectric |= m.metallic == 0.0f && m.perceptual_roughness >= 0.4f && m.perceptual_roughness < 1.0f;
    glossy_metal |= m.metallic == 1.0f && std::abs(m.perceptual_roughness - 0.3f) < 0.05f;
  }
  ASSERT_TRUE(rough_dielectric && glossy_metal);
  expect_agreement(gpu_vs_embree(scene, scene));
}

// The comparison can fail: 5% less albedo in the Embree scene only.
TEST(ReferenceAgreement, FivePercentAlbedoChangeIsRejected) {
  const Scene scene = make_cornell_box();
  const Comparison c = gpu_vs_embree(scene, scaled_albedo(scene, 0.95f));
  const ComparisonVerdict v = c.judge(kNoiseFactor, kEnergyTolerance);
  EXPECT_FALSE(v.passed);
  EXPECT_FALSE(v.inconclusive) << v.reason;
  EXPECT_GT(c.energy_ratio, 1.0 + kEnergyTolerance);
}

TEST(ReferenceAgreement, FivePercentAlbedoChangeIsRejectedOnGltfScene) {
  const Scene scene = import_gltf(test::source_dir() / "scenarios/assets/glossy_room.gltf");
  const Comparison c = gpu_vs_embree(scaled_albedo(scene, 0.95f), scene);
  const ComparisonVerdict v = c.judge(kNoiseFactor, kEnergyTolerance);
  EXPECT_FALSE(v.passed);
  EXPECT_FALSE(v.inconclusive) << v.reason;
}

}  // namespace
}  // namespace gi
