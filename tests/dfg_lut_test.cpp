// The material models of brdf.model (core/shared/brdf.h) and the DFG table
// BRDF_LAYERED reads (core/shared/dfg_lut.h, baked by core/dfg_lut_bake.cpp).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/dfg_lut_bake.h"
#include "core/reference/reference_cache.h"
#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "core/shared/brdf.h"
#include "core/profile.h"
#include "gpu/realtime_settings.h"
#include "tests/test_support.h"

namespace {

using namespace gi::shader;

// The committed table is the bake, texel for texel. The half-precision values
// may differ by one unit in the last place where a libm rounds differently.
TEST(DfgLut, CommittedTableIsTheBake) {
  const std::vector<std::uint32_t> baked = gi::bake_dfg_lut();
  if (std::getenv("GIHARNESS_UPDATE_DFG_LUT")) {
    gi::write_text_file(gi::test::source_dir() / "core/shared/dfg_lut.h", gi::dfg_lut_header(baked));
    GTEST_SKIP() << "wrote core/shared/dfg_lut.h; rebuild and run again";
  }
  ASSERT_EQ(baked.size(), std::size_t(DFG_LUT_SIZE) * DFG_LUT_SIZE);
  std::size_t exact = 0;
  for (std::size_t i = 0; i < baked.size(); ++i) {
    for (int half = 0; half < 2; ++half) {
      const int a = int((baked[i] >> (16 * half)) & 0xffffu), b = int((DFG_LUT[i] >> (16 * half)) & 0xffffu);
      ASSERT_LE(std::abs(a - b), 1) << "texel " << i;
    }
    exact += baked[i] == DFG_LUT[i];
  }
  EXPECT_GE(exact, baked.size() * 99 / 100);
}

// Directional albedo ∫ f cos dl of a material under a model, by a 256² midpoint
// rule over the hemisphere (cos-weighted: dl = cos-hemisphere sample / (cos/π)).
vec3 albedo(const BrdfParams& p, float nov) {
  const vec3 n(0.0f, 0.0f, 1.0f), v(std::sqrt(1.0f - nov * nov), 0.0f, nov);
  dvec3 sum(0.0);
  const int m = 256;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const vec3 l = sample_cosine_hemisphere(vec2((i + 0.5f) / m, (j + 0.5f) / m));
      sum += dvec3(brdf_eval(p, n, v, l) * PI);
    }
  return vec3(sum / double(m * m));
}

BrdfParams white_metal(float perceptual_roughness, uint model) {
  return brdf_params(vec3(1.0f), 1.0f, perceptual_roughness, 0.5f, model);
}

// The table's limits (smooth, head on: all scale, no bias) and its sum
// A + B against the single-scatter lobe's albedo integrated directly over
// the hemisphere (F0 = 1: F = 1), which it must equal; at α = 1 head on
// that is 1 − ln 2 = 0.307 (D = 1/π, V = 1 / (2 (n·l + 1))).
TEST(DfgLut, TableIsTheSingleScatterAlbedo) {
  const vec2 smooth = dfg_lut_f_ab(1.0f, 0.0f);
  EXPECT_NEAR(smooth.x, 1.0f, 0.01f);
  EXPECT_NEAR(smooth.y, 0.0f, 0.01f);
  for (float pr : {0.3f, 0.6f, 1.0f})
    for (float nov : {0.1f, 0.4f, 0.8f, 1.0f}) {
      const vec2 f = dfg_lut_f_ab(nov, pr);
      // The midpoint rule resolves a narrow lobe at grazing only to ~3 %.
      const float tolerance = nov < 0.2f ? 0.035f : 0.012f;
      EXPECT_NEAR(f.x + f.y, albedo(white_metal(pr, BRDF_SINGLE_SCATTER), nov).x, tolerance) << pr << " " << nov;
    }
  EXPECT_NEAR(albedo(white_metal(1.0f, BRDF_SINGLE_SCATTER), 1.0f).x, 1.0f - std::log(2.0f), 0.002f);
}

// 0.17 and 0.18 divide by F_ab.x (the scale) of Karis's polynomial where
// Filament divides by the single-scatter albedo: a white metal reflects up
// to 1.8 times what it receives (20 % more head on at moderate roughness).
// 0.19 divides by F_ab.x + F_ab.y of the table (#23514, #23737) and keeps a
// white furnace near 1. The single-scatter model loses energy instead.
TEST(BrdfModels, MultiscatterFactorIsBevysAtEachRelease) {
  for (float pr : {0.3f, 0.6f, 1.0f})
    for (float nov : {0.1f, 0.4f, 0.8f, 1.0f}) {
      const float single = albedo(white_metal(pr, BRDF_SINGLE_SCATTER), nov).x;
      const float approx = albedo(white_metal(pr, BRDF_MULTISCATTER_APPROX), nov).x;
      const float layered = albedo(white_metal(pr, BRDF_LAYERED), nov).x;
      EXPECT_LT(single, 0.995f);
      EXPECT_NEAR(approx, single / F_ab_polynomial(pr, nov).x, 0.01f) << pr << " " << nov;
      if (pr < 1.0f) EXPECT_GT(approx, 1.15f) << pr << " " << nov;
      EXPECT_NEAR(layered, 1.0f, 0.035f) << pr << " " << nov;
    }
}

// 0.19's layered diffuse: a white dielectric loses what its Fresnel reflects,
// most at grazing angles, and 0.19's f90 = 1 makes reflectance 0 reflect at
// grazing too (the Cornell box's walls are no longer pure Lambert).
TEST(BrdfModels, LayeredDiffuseLosesWhatFresnelReflects) {
  const vec3 n(0.0f, 0.0f, 1.0f), l = normalize(vec3(0.3f, 0.0f, 1.0f));
  for (float reflectance : {0.0f, 0.5f}) {
    const BrdfParams flat = brdf_params(vec3(0.8f), 0.0f, 0.6f, reflectance, BRDF_MULTISCATTER_APPROX);
    const BrdfParams layered = brdf_params(vec3(0.8f), 0.0f, 0.6f, reflectance, BRDF_LAYERED);
    const vec3 head_on(0.0f, 0.0f, 1.0f), grazing = normalize(vec3(1.0f, 0.0f, 0.08f));
    EXPECT_FLOAT_EQ(brdf_eval_diffuse(flat, n, grazing, l).x, 0.8f * INV_PI);
    const float at_head_on = brdf_eval_diffuse(layered, n, head_on, l).x / (0.8f * INV_PI);
    const float at_grazing = brdf_eval_diffuse(layered, n, grazing, l).x / (0.8f * INV_PI);
    EXPECT_LT(at_head_on, 1.0f);
    EXPECT_GT(at_head_on, 0.9f);
    EXPECT_LT(at_grazing, at_head_on - 0.3f) << reflectance;
  }
  // Reflectance 0: no specular under the earlier Fresnel, a grazing one under 0.19's.
  const vec3 v = normalize(vec3(-1.0f, 0.0f, 0.05f)), mirror_l = normalize(vec3(1.0f, 0.0f, 0.05f));
  EXPECT_EQ(specular_lobe(brdf_params(vec3(0.8f), 0.0f, 0.3f, 0.0f, BRDF_MULTISCATTER_APPROX), vec3(0, 0, 1), v,
                          mirror_l).x, 0.0f);
  EXPECT_GT(specular_lobe(brdf_params(vec3(0.8f), 0.0f, 0.3f, 0.0f, BRDF_LAYERED), vec3(0, 0, 1), v, mirror_l).x,
            0.1f);
}

// The model travels with the materials, so the Embree reference renders
// with it and caches each model's image under its own key.
TEST(BrdfModels, MaterialsCarryTheModelIntoTheReference) {
  gi::Scene scene = gi::make_cornell_box();
  gi::ReferenceOptions o;
  o.width = o.height = 8;
  o.spp = 2;
  const std::uint64_t single = gi::reference_cache_key(scene, o);
  scene.brdf_model = BRDF_LAYERED;
  const gi::FlatInstances flat = gi::flatten_instances(scene, gi::flatten_geometry(scene));
  for (const GpuMaterial& m : flat.materials) EXPECT_EQ(uint(m.reflectance.y), BRDF_LAYERED);
  EXPECT_NE(gi::reference_cache_key(scene, o), single);
}

// #24668's flags ride above the model: brdf_params keeps them apart, the
// model compares as before, and only the raw argument lets Fresnel see a
// cosine above 1 (on the GPU, pow of the negative base is NaN; std::pow of
// a negative base to the integral power 5 stays finite, so C++ shows the
// sign, not the NaN).
TEST(BrdfModels, FresnelArgumentAndClampFlagsRideAboveTheModel) {
  const BrdfParams plain = brdf_params(vec3(0.9f), 1.0f, 0.05f, 0.5f, BRDF_LOBES);
  const BrdfParams raw = brdf_params(vec3(0.9f), 1.0f, 0.05f, 0.5f, BRDF_LOBES | BRDF_FRESNEL_RAW);
  const BrdfParams clamped =
      brdf_params(vec3(0.9f), 1.0f, 0.05f, 0.5f, BRDF_LOBES | BRDF_FRESNEL_RAW | BRDF_EVALUATE_CLAMP);
  EXPECT_EQ(raw.model, BRDF_LOBES);
  EXPECT_EQ(raw.flags, BRDF_FRESNEL_RAW);
  EXPECT_EQ(clamped.flags, BRDF_FRESNEL_RAW | BRDF_EVALUATE_CLAMP);
  EXPECT_EQ(plain.flags, 0u);
  const float above = 1.0f + 1e-6f;
  EXPECT_EQ(fresnel_cos(plain, above), 1.0f);
  EXPECT_EQ(fresnel_cos(raw, above), above);
  EXPECT_LT(1.0f - fresnel_cos(raw, above), 0.0f);  // the base pow() gets on the GPU
  // Away from the rounding the flags change nothing.
  const vec3 n(0, 0, 1), v = glm::normalize(vec3(0.3f, 0.1f, 1.0f)), l = glm::normalize(vec3(-0.28f, -0.1f, 1.0f));
  const vec3 f = brdf_eval(plain, n, v, l);
  EXPECT_EQ(brdf_eval(raw, n, v, l), f);
  EXPECT_EQ(brdf_eval(clamped, n, v, l), f);
}

// The profile puts the flags on every material (as the GPU passes and the
// Embree reference read them): 0.19 feeds Fresnel the raw cosine, main clamps.
TEST(BrdfModels, ProfilesSetTheNanFlags) {
  for (const auto& [profile, fresnel_raw] : {std::pair{"solari-0.17", false}, {"solari-0.18", false}, {"solari-0.19", true}}) {
    gi::Scene scene = gi::make_cornell_box();
    gi::apply_material_model(scene, gi::load_profile(profile));
    EXPECT_EQ((scene.brdf_model & BRDF_FRESNEL_RAW) != 0u, fresnel_raw) << profile;
    EXPECT_EQ(scene.brdf_model & BRDF_EVALUATE_CLAMP, 0u) << profile;  // no release clamps
  }
}

}  // namespace
