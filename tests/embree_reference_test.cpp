// The Embree reference path tracer, its cache, EXR I/O and the image metrics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include <unistd.h>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "core/errors.h"
#include "core/exr_io.h"
#include "core/metrics.h"
#include "core/reference/embree_reference.h"
#include "core/reference/reference_cache.h"
#include "core/scenes/cornell_box.h"
#include "core/scenes/mesh_builder.h"
#include "core/shared/brdf.h"
#include "core/shared/rng.h"

namespace gi {
namespace {

bool same_bits(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.size() == b.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.size() * sizeof(glm::vec3)) == 0;
}

// A fresh, empty directory under the test temp dir.
std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path d = std::filesystem::path(::testing::TempDir()) / ("giharness_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// --- (1) an analytic scene --------------------------------------------------

// A closed cube, all six faces facing inwards, one material: diffuse base
// colour a, emission Le, roughness 1, reflectance 0. For a Lambert surface
// radiance is Le / (1 − a) everywhere. The shared BRDF keeps Schlick's grazing
// term even at reflectance 0 (f0 = 0), a specular lobe of directional albedo
// ρs(v) ∈ [0, ρs,max] on top of a; so the exact answer lies in
// [Le / (1 − a), Le / (1 − a − ρs,max)] (sup-norm bounds of the transport).
Scene closed_box(glm::vec3 albedo, glm::vec3 emission, glm::vec3 offset) {
  Scene s;
  s.name = "closed_box";
  Mesh m;
  m.name = "box";
  const glm::vec3 c(0.0f);
  const float h = 1.0f;
  auto P = [h](float x, float y, float z) { return glm::vec3(x * h, y * h, z * h); };
  add_quad(m, P(-1, -1, -1), P(1, -1, -1), P(1, -1, 1), P(-1, -1, 1), c);
  add_quad(m, P(-1, 1, -1), P(1, 1, -1), P(1, 1, 1), P(-1, 1, 1), c);
  add_quad(m, P(-1, -1, -1), P(-1, 1, -1), P(-1, 1, 1), P(-1, -1, 1), c);
  add_quad(m, P(1, -1, -1), P(1, 1, -1), P(1, 1, 1), P(1, -1, 1), c);
  add_quad(m, P(-1, -1, -1), P(1, -1, -1), P(1, 1, -1), P(-1, 1, -1), c);
  add_quad(m, P(-1, -1, 1), P(1, -1, 1), P(1, 1, 1), P(-1, 1, 1), c);
  Material mat;
  mat.name = "grey_emitter";
  mat.base_color = albedo;
  mat.metallic = 0.0f;
  mat.perceptual_roughness = 1.0f;
  mat.reflectance = 0.0f;
  mat.emissive = emission;
  add_object(s, std::move(m), mat, glm::translate(glm::mat4(1.0f), offset));
  s.camera.position = offset + glm::vec3(0.2f, -0.1f, 0.3f);
  s.camera.target = offset + glm::vec3(1.0f, 0.5f, 1.0f);
  s.camera.vertical_fov_degrees = 100.0f;
  return s;
}

// Directional albedo of the specular part of brdf_params(white, 0, 1, 0, BRDF_SINGLE_SCATTER) at
// n·v = 0.01 (where Schlick's term would be largest), by Monte Carlo. With
// Filament's f90 a reflectance of 0 has no specular lobe at all.
double max_specular_albedo() {
  using namespace shader;
  const BrdfParams p = brdf_params(glm::vec3(1.0f), 0.0f, 1.0f, 0.0f, BRDF_SINGLE_SCATTER);
  const glm::vec3 n(0.0f, 0.0f, 1.0f), v(std::sqrt(1.0f - 1e-4f), 0.0f, 0.01f);
  uint state = 99u;
  double sum = 0;
  const int kDraws = 400000;
  for (int i = 0; i < kDraws; ++i) {
    const glm::vec3 l = sample_uniform_hemisphere(rng_next_vec2(state));
    sum += double((brdf_eval(p, n, v, l).x - INV_PI) * l.z) * TWO_PI;
  }
  return sum / kDraws;
}

// Renders the box at `offset` (24×24, 64 spp: SE ≈ 0.1-0.3% of the mean) and
// checks each channel's image mean m against Le/(1−a) (pure Lambert: the
// specular albedo is 0) within 5 standard errors.
// Any leak (rays escaping the closed box), lost light sample or missed MIS
// weight pushes m below Le/(1−a); double counting pushes it far above.
void expect_closed_box_radiance(glm::vec3 offset) {
  const glm::vec3 a(0.3f, 0.5f, 0.7f), le(1.0f, 0.5f, 0.25f);
  const Scene scene = closed_box(a, le, offset);
  ReferenceOptions o;
  o.width = o.height = 24;
  o.spp = 64;
  const ReferenceResult r = render_reference(scene, o);
  EXPECT_EQ(r.nonfinite_samples, 0u);
  EXPECT_GT(r.rays, std::uint64_t(o.width) * o.height * o.spp);

  const double rho_s = max_specular_albedo();
  EXPECT_EQ(rho_s, 0.0);
  const double P = double(r.mean.size());
  for (int c = 0; c < 3; ++c) {
    // SE of the image mean from the halves (pixels are independent):
    // SE = sqrt(Σ (a_p − b_p)² / 4) / P.
    double mean = 0, var = 0;
    for (std::size_t i = 0; i < r.mean.size(); ++i) {
      mean += r.mean.pixels[i][c];
      const double d = double(r.half_a.pixels[i][c]) - double(r.half_b.pixels[i][c]);
      var += d * d / 4.0;
    }
    mean /= P;
    const double se = std::sqrt(var) / P;
    const double lambert = le[c] / (1.0 - a[c]);
    SCOPED_TRACE(::testing::Message() << "channel " << c << ": mean " << mean << ", SE " << se << ", Le/(1-a) "
                                      << lambert);
    EXPECT_LT(se, 0.01 * lambert);  // the test has power
    EXPECT_NEAR(mean, lambert, 5.0 * se);
  }
}

TEST(EmbreeReference, ClosedBoxRadianceIsLeOverOneMinusAlbedo) { expect_closed_box_radiance(glm::vec3(0.0f)); }

// The same box 10 units from the origin: the spawn offset grows with the
// coordinates (1e-4 × max|p|), and shadow rays must not end past the light.
TEST(EmbreeReference, ClosedBoxAwayFromOrigin) { expect_closed_box_radiance(glm::vec3(10.0f, -3.0f, 2.0f)); }

// --- (2) determinism ----------------------------------------------------------

TEST(EmbreeReference, BitIdenticalAtAnyThreadCount) {
  const Scene scene = make_cornell_box();
  ReferenceOptions o;
  o.width = o.height = 32;
  o.spp = 8;
  o.threads = 1;
  const ReferenceResult one = render_reference(scene, o);
  o.threads = 2;
  const ReferenceResult two = render_reference(scene, o);
  EXPECT_TRUE(same_bits(one.mean, two.mean));
  EXPECT_TRUE(same_bits(one.half_a, two.half_a));
  EXPECT_TRUE(same_bits(one.half_b, two.half_b));
  EXPECT_EQ(one.rays, two.rays);
  EXPECT_EQ(one.nonfinite_samples, two.nonfinite_samples);
  // And a different seed gives a different image.
  o.seed = 2;
  EXPECT_FALSE(same_bits(render_reference(scene, o).mean, one.mean));
}

// --- (3) Cornell box: independent halves, noise estimate, cache ----------------

// Two renders with different seeds differ by noise only, so relMSE(X, Y)
// should equal the noise both estimate from their own halves (ratio ≈ 1).
// Correlated halves would make the halves agree too well and the ratio ≫ 1.
// The range [0.6, 1.7] allows for the ratio's own scatter at 32×32 (heavy
// tails of a few bright pixels).
TEST(EmbreeReference, CornellHalvesAreIndependentAndNoiseIsCalibrated) {
  const Scene scene = make_cornell_box();
  ReferenceOptions o;
  o.width = o.height = 32;
  o.spp = 128;
  const ReferenceResult x = render_reference(scene, o);
  o.seed = 2;
  const ReferenceResult y = render_reference(scene, o);
  EXPECT_EQ(x.nonfinite_samples + y.nonfinite_samples, 0u);
  const Comparison c = compare(x.mean, x.half_a, x.half_b, y.mean, y.half_a, y.half_b);
  std::printf("relmse %.5g noise %.5g + %.5g ratio %.3f energy %.4f ± %.4f\n", c.relmse, c.noise_x, c.noise_y,
              c.relmse_over_noise, c.energy_ratio, c.energy_ratio_sigma);
  EXPECT_GT(c.relmse_over_noise, 0.6);
  EXPECT_LT(c.relmse_over_noise, 1.7);
  // Same renderer, no bias: passes within 3× noise and 5% energy.
  const ComparisonVerdict v = c.judge(3.0, 0.05);
  EXPECT_TRUE(v.passed) << v.reason;
  // A 1% energy tolerance cannot be checked with this much noise.
  const ComparisonVerdict tight = c.judge(3.0, c.energy_ratio_sigma);
  EXPECT_TRUE(tight.inconclusive) << tight.reason;
  // A brighter light is caught.
  CornellBoxOptions brighter;
  brighter.light_scale = 1.3f;
  o.seed = 3;
  const ReferenceResult z = render_reference(make_cornell_box(brighter), o);
  const ComparisonVerdict bad = compare(z.mean, z.half_a, z.half_b, y.mean, y.half_a, y.half_b).judge(3.0, 0.05);
  EXPECT_FALSE(bad.passed);
  EXPECT_FALSE(bad.inconclusive) << bad.reason;
}

TEST(EmbreeReference, CacheReturnsIdenticalBits) {
  const std::filesystem::path dir = fresh_dir("refcache");
  const Scene scene = make_cornell_box();
  ReferenceOptions o;
  o.width = o.height = 32;
  o.spp = 8;
  bool hit = true;
  const ReferenceResult first = cached_reference(scene, o, dir, &hit);
  ASSERT_FALSE(reference_integrator_version().empty()) << "sources not found: caching is off";
  EXPECT_FALSE(hit);
  o.threads = 1;  // not part of the key
  const ReferenceResult second = cached_reference(scene, o, dir, &hit);
  EXPECT_TRUE(hit);
  EXPECT_TRUE(same_bits(first.mean, second.mean));
  EXPECT_TRUE(same_bits(first.half_a, second.half_a));
  EXPECT_TRUE(same_bits(first.half_b, second.half_b));
  EXPECT_EQ(first.rays, second.rays);
  EXPECT_EQ(first.nonfinite_samples, second.nonfinite_samples);
  // Anything that changes the image changes the key.
  ReferenceOptions more = o;
  more.spp = 9;
  EXPECT_NE(reference_cache_key(scene, o), reference_cache_key(scene, more));
  Scene moved = scene;
  moved.instances[0].emissive_scale = glm::vec3(0.5f);
  EXPECT_NE(reference_cache_key(scene, o), reference_cache_key(moved, o));
  Scene hidden = scene;
  hidden.instances[3].visible = false;
  EXPECT_NE(reference_cache_key(scene, o), reference_cache_key(hidden, o));
  // A corrupt sidecar is a miss, and the re-render gives the same bits.
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".json") std::ofstream(e.path()) << "{ not json";
  const ReferenceResult third = cached_reference(scene, o, dir, &hit);
  EXPECT_FALSE(hit);
  EXPECT_TRUE(same_bits(first.mean, third.mean));
  // No temporary file is left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  std::filesystem::remove_all(dir);
}

// Seeds (the references committed with the baselines) serve a cache miss
// with the bits the seed's machine rendered, and land in the cache; a seed of
// another integrator version is never read, and updating the seeds removes it.
TEST(EmbreeReference, SeedsServeAMissAndGoWhenTheirVersionDoes) {
  const std::filesystem::path dir = fresh_dir("refseeds");
  const Scene scene = make_cornell_box();
  ReferenceOptions o;
  o.width = o.height = 16;
  o.spp = 4;
  bool hit = true;
  const ReferenceResult rendered = cached_reference(scene, o, dir / "first_cache", dir / "no_seeds", &hit);
  EXPECT_FALSE(hit);
  const std::string stem = "reference-" + fmt::format("{:016x}", reference_cache_key(scene, o));
  const std::vector<std::string> used = reference_entries_used();
  EXPECT_NE(std::find(used.begin(), used.end(), stem), used.end());

  // A stale seed: another version's sidecar beside a copy of the EXR.
  std::filesystem::create_directories(dir / "seeds");
  std::filesystem::copy_file(dir / "first_cache" / (stem + ".exr"), dir / "seeds/reference-00000000000000aa.exr");
  std::ofstream(dir / "seeds/reference-00000000000000aa.json") << R"({"key": "00000000000000aa", "version": "old"})";
  const ReferenceSeeds kept = keep_reference_seeds({stem, "reference-not-in-the-cache"}, dir / "first_cache", dir / "seeds");
  EXPECT_EQ(kept.added, 1u);
  EXPECT_EQ(kept.removed, 1u);
  EXPECT_EQ(kept.entries, 1u);
  EXPECT_GT(kept.bytes, 0u);
  EXPECT_FALSE(std::filesystem::exists(dir / "seeds/reference-00000000000000aa.exr"));

  // A fresh cache: the seed serves the miss, bit for bit, and is copied in.
  const ReferenceResult seeded = cached_reference(scene, o, dir / "fresh_cache", dir / "seeds", &hit);
  EXPECT_TRUE(hit);
  EXPECT_TRUE(same_bits(rendered.mean, seeded.mean));
  EXPECT_TRUE(same_bits(rendered.half_b, seeded.half_b));
  EXPECT_TRUE(std::filesystem::exists(dir / "fresh_cache" / (stem + ".json")));
  // Another key is not in the seeds: rendered.
  ReferenceOptions other = o;
  other.spp = 5;
  cached_reference(scene, other, dir / "other_cache", dir / "seeds", &hit);
  EXPECT_FALSE(hit);
  std::filesystem::remove_all(dir);
}

// The background is seen where the camera ray misses and lights nothing: a
// pixel either gains exactly it or nothing, in the path tracer and in the
// direct-lighting reference, and it is part of the cache key.
TEST(EmbreeReference, BackgroundShowsOnlyWhereTheCameraRayMisses) {
  Scene scene = make_cornell_box();
  scene.camera.position = glm::vec3(0.278f, 0.273f, -2.0f);  // far back: the box fills the middle
  ReferenceOptions o;
  o.width = 32;
  o.height = 24;
  o.spp = 4;
  for (const bool direct : {false, true}) {
    SCOPED_TRACE(direct ? "direct" : "path");
    o.direct_only = direct;
    Scene lit = scene;
    lit.background = glm::vec3(0.25f, 0.5f, 1.0f);
    const ReferenceResult black = render_reference(scene, o), shown = render_reference(lit, o);
    std::size_t sky = 0, box = 0;
    for (std::size_t i = 0; i < black.mean.pixels.size(); ++i) {
      const glm::vec3 d = shown.mean.pixels[i] - black.mean.pixels[i];
      if (d == glm::vec3(0.0f)) {
        ++box;
      } else {
        ++sky;
        EXPECT_NEAR(d.x, 0.25f, 1e-5f);
        EXPECT_NEAR(d.y, 0.5f, 1e-5f);
        EXPECT_NEAR(d.z, 1.0f, 1e-5f);
      }
    }
    EXPECT_GT(sky, 0u);
    EXPECT_GT(box, 50u);  // the box: about 100 of the 768 pixels
    EXPECT_NE(reference_cache_key(scene, o), reference_cache_key(lit, o));
  }
}

// --- EXR I/O --------------------------------------------------------------------

TEST(ExrIo, MultiLayerRoundTripIsExact) {
  const std::filesystem::path dir = fresh_dir("exr");
  Image rgb(5, 3), di(5, 3);
  for (std::uint32_t i = 0; i < rgb.size(); ++i) {
    rgb.pixels[i] = glm::vec3(float(i), -1.5f * i, 1e-30f * i);
    di.pixels[i] = glm::vec3(1e30f, 0.1f * i, std::ldexp(1.0f, -i));
  }
  write_exr(dir / "a.exr", {{"", &rgb}, {"di", &di}});
  const std::map<std::string, Image> back = read_exr(dir / "a.exr");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_TRUE(same_bits(back.at(""), rgb));
  EXPECT_TRUE(same_bits(back.at("di"), di));
  EXPECT_THROW(read_exr(dir / "missing.exr"), InputError);
  std::ofstream(dir / "junk.exr") << "not an exr file";
  EXPECT_THROW(read_exr(dir / "junk.exr"), InputError);
  Image other(2, 2);
  EXPECT_THROW(write_exr(dir / "b.exr", {{"", &rgb}, {"x", &other}}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "b.exr"));
  std::filesystem::remove_all(dir);
}

// --- (4) metrics on hand-made images ---------------------------------------------

Image image(std::initializer_list<glm::vec3> px) {
  Image im(std::uint32_t(px.size()), 1);
  std::copy(px.begin(), px.end(), im.pixels.begin());
  return im;
}

TEST(Metrics, HandComputedValues) {
  const Image x = image({{1, 1, 1}, {2, 0, 0}});
  const Image y = image({{1, 1, 1}, {1, 0, 0}});
  // One channel differs by 1 where y = 1: (1)² / (1 + 0.01) over 6 values.
  EXPECT_NEAR(relmse(x, y), (1.0 / 1.01) / 6.0, 1e-12);
  EXPECT_NEAR(mean_abs_error(x, y), 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(mean_rel_error(x, y), (1.0 / std::sqrt(1.01)) / 6.0, 1e-12);
  // Luminance weights sum to 1: lum(x) = (1 + 2·0.2126)/2, lum(y) = (1 + 0.2126)/2.
  EXPECT_NEAR(energy_ratio(x, y), (1.0 + 2 * 0.2126) / (1.0 + 0.2126), 1e-6);
  EXPECT_NEAR(max_luminance_ratio(x, y), 1.0, 1e-6);
  EXPECT_NEAR(max_luminance_ratio(image({{0, 3, 0}}), image({{0, 1, 0}})), 3.0, 1e-6);
  EXPECT_EQ(relmse(y, y), 0.0);
  EXPECT_EQ(energy_ratio(y, y), 1.0);

  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const Image bad = image({{nan, 1, 1}, {2, 0, inf}, {0, 0, 0}});
  EXPECT_EQ(count_nonfinite(bad), 2u);
  // Non-finite pixels are left out of the means: only the last pixel counts.
  EXPECT_EQ(relmse(bad, image({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}})), 0.0);

  // Halves 1 and 3 with reference 2 in R: (2)² / (4 + 0.01) / 3 channels / 4.
  EXPECT_NEAR(estimator_noise(image({{1, 1, 1}}), image({{3, 1, 1}}), image({{2, 1, 1}})), 4.0 / 4.01 / 3.0 / 4.0,
              1e-12);
  // σ of the mean luminance: |Δlum| = 2·0.2126 per pixel, two pixels: sqrt(2·(0.4252)²/4)/2.
  EXPECT_NEAR(mean_luminance_sigma(image({{1, 0, 0}, {3, 0, 0}}), image({{3, 0, 0}, {1, 0, 0}})),
              std::sqrt(2 * 0.4252 * 0.4252 / 4) / 2, 1e-6);
}

TEST(Metrics, ComparisonVerdicts) {
  // Noise-free and equal: passes.
  const Image y = image({{1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}});
  Comparison same = compare(y, y, y, y, y, y);
  EXPECT_EQ(same.relmse, 0.0);
  EXPECT_EQ(same.combined_noise, 0.0);
  EXPECT_TRUE(same.passes(3.0, 0.01));

  // Equal means but very noisy halves: nothing can be concluded at 1% energy.
  const Image lo = image({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}});
  const Image hi = image({{2, 2, 2}, {3, 3, 3}, {4, 4, 4}, {5, 5, 5}});
  Comparison noisy = compare(y, lo, hi, y, lo, hi);
  const ComparisonVerdict v = noisy.judge(3.0, 0.01);
  EXPECT_FALSE(v.passed);
  EXPECT_TRUE(v.inconclusive) << v.reason;
  EXPECT_TRUE(noisy.inconclusive(3.0, 0.01));
  // ... nor against an absolute relMSE tolerance below the noise.
  EXPECT_TRUE(noisy.judge(3.0, 10.0, 1e-3).inconclusive);

  // Twice as bright, no noise: a definite failure, not inconclusive.
  Image x2 = y;
  for (glm::vec3& p : x2.pixels) p *= 2.0f;
  const ComparisonVerdict f = compare(x2, x2, x2, y, y, y).judge(3.0, 0.05);
  EXPECT_FALSE(f.passed);
  EXPECT_FALSE(f.inconclusive);
  EXPECT_NEAR(compare(x2, x2, x2, y, y, y).energy_ratio, 2.0, 1e-9);

  // Non-finite values always fail.
  Image xn = y;
  xn.pixels[1].y = std::numeric_limits<float>::quiet_NaN();
  const Comparison cn = compare(xn, xn, xn, y, y, y);
  EXPECT_EQ(cn.nonfinite_x, 1u);
  EXPECT_FALSE(cn.judge(3.0, 0.05).passed);
  EXPECT_FALSE(cn.judge(3.0, 0.05).inconclusive);
}

}  // namespace
}  // namespace gi
