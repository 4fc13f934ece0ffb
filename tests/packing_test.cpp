// CPU tests of core/shared/packing.h and light_tiles.h, the very code the
// light-tile shader runs: rgb9e5 (plain and log2) round-trip bounds,
// octahedral unit vectors, the 24-byte light sample.
#include <gtest/gtest.h>

#include <cmath>

#include "core/shared/light_tiles.h"
#include "core/shared/packing.h"
#include "core/shared/rng.h"

namespace {

using namespace gi::shader;

float rand01(uint& s) { return rng_next_float(s); }

TEST(Rgb9e5, PlainRoundTripErrorIsAtMostHalfAStepOfTheLargestChannel) {
  uint s = 12345u;
  for (int i = 0; i < 20000; ++i) {
    // Magnitudes from 2^-14 to 2^15, channels up to 3 decades apart.
    const float scale = std::exp2(-14.0f + 29.0f * rand01(s));
    const vec3 v = scale * vec3(rand01(s), std::pow(rand01(s), 3.0f), rand01(s) * 0.001f + 0.5f);
    const vec3 back = rgb9e5_to_vec3(vec3_to_rgb9e5(v));
    const float bound = max3(v) / 512.0f * 1.0001f;  // the mantissa step is ≤ max / 256
    for (int c = 0; c < 3; ++c) ASSERT_LE(std::abs(back[c] - v[c]), bound) << "value " << v[c] << " channel " << c;
  }
}

TEST(Rgb9e5, PlainClipsAboveItsRangeAndFlushesNegatives) {
  EXPECT_FLOAT_EQ(rgb9e5_to_vec3(vec3_to_rgb9e5(vec3(1e6f, 1.0f, -3.0f))).x, RGB9E5_MAX);
  EXPECT_EQ(rgb9e5_to_vec3(vec3_to_rgb9e5(vec3(1e6f, 1.0f, -3.0f))).z, 0.0f);
  EXPECT_EQ(rgb9e5_to_vec3(vec3_to_rgb9e5(vec3(0.0f))), vec3(0.0f));
}

TEST(Rgb9e5, Log2RoundTripRelativeErrorFollowsTheLogStep) {
  uint s = 777u;
  for (const float exposure : {1.0f, 0.001f}) {
    for (int i = 0; i < 20000; ++i) {
      const float L = std::exp2(-10.0f + 40.0f * rand01(s));
      const vec3 v = L * vec3(1.0f, 0.2f + 0.8f * rand01(s), 0.05f + 0.95f * rand01(s));
      const vec3 back = unpack_radiance_log2(pack_radiance_log2(v, exposure), exposure);
      const float max_log = max3(log2(v * exposure + vec3(1.0f)));
      // |Δ log2(L·e + 1)| ≤ max_log / 512 in every channel.
      const float bound = std::exp2(max_log / 512.0f) - 1.0f + 1e-5f;
      for (int c = 0; c < 3; ++c) {
        const float ratio = (back[c] * exposure + 1.0f) / (v[c] * exposure + 1.0f);
        ASSERT_LE(std::abs(ratio - 1.0f), bound) << "L " << v[c] << " exposure " << exposure;
      }
    }
  }
}

TEST(Rgb9e5, Log2KeepsRadianceThatPlainClips) {
  const vec3 bright(2e5f, 1e5f, 5e4f);
  const vec3 plain = unpack_radiance_plain(pack_radiance_plain(bright, 1.0f), 1.0f);
  const vec3 log2v = unpack_radiance_log2(pack_radiance_log2(bright, 1.0f), 1.0f);
  EXPECT_LT(luminance(plain) / luminance(bright), 0.6f);                // clipped to 65408
  EXPECT_NEAR(luminance(log2v) / luminance(bright), 1.0f, 0.03f);       // log step at 2^17.6
}

TEST(Octahedral, UnitVectorsRoundTripWithin16BitPrecision) {
  uint s = 99u;
  float worst = 0.0f;
  for (int i = 0; i < 20000; ++i) {
    vec3 n = normalize(vec3(2.0f * rand01(s) - 1.0f, 2.0f * rand01(s) - 1.0f, 2.0f * rand01(s) - 1.0f));
    const vec3 back = unpack_unit_vector(pack_unit_vector(n));
    ASSERT_NEAR(length(back), 1.0f, 1e-5f);
    // atan2(|n × b|, n · b) in double: acos of a float dot cannot resolve
    // angles below ~3e-4 (1 − ulp).
    const glm::dvec3 dn(n), db(back);
    worst = std::max(worst, float(std::atan2(glm::length(glm::cross(dn, db)), glm::dot(dn, db))));
  }
  EXPECT_LT(worst, 1e-4f);  // a 16-bit step is 3e-5 of the octahedron's [-1, 1] side
  for (vec3 axis : {vec3(0, 0, 1), vec3(0, 0, -1), vec3(1, 0, 0), vec3(0, -1, 0)})
    EXPECT_GT(dot(unpack_unit_vector(pack_unit_vector(axis)), axis), 0.99999f);
}

TEST(LightTiles, PackedSampleIs24BytesAndRoundTrips) {
  static_assert(sizeof(PackedLightSample) == 24);
  ResolvedLightSample s;
  s.world_position = vec4(1.5f, -2.0f, 3.25f, 1.0f);
  s.world_normal = normalize(vec3(0.2f, -1.0f, 0.1f));
  s.radiance = vec3(17.0f, 12.0f, 4.0f);
  s.inverse_pdf = 0.75f;
  for (bool log2_radiance : {true, false}) {
    const ResolvedLightSample b = unpack_light_sample(pack_light_sample(s, 1.0f, log2_radiance), 1.0f, log2_radiance);
    EXPECT_EQ(vec3(b.world_position), vec3(s.world_position));
    EXPECT_EQ(b.world_position.w, 1.0f);
    EXPECT_EQ(b.inverse_pdf, 0.75f);
    EXPECT_GT(dot(b.world_normal, s.world_normal), 0.99999f);
    EXPECT_NEAR(luminance(b.radiance) / luminance(s.radiance), 1.0f, 0.01f);
  }
  s.world_position.w = 0.0f;  // directional: the sign of the inverse pdf carries it
  const ResolvedLightSample d = unpack_light_sample(pack_light_sample(s, 1.0f, true), 1.0f, true);
  EXPECT_EQ(d.world_position.w, 0.0f);
  EXPECT_EQ(d.inverse_pdf, 0.75f);
}

}  // namespace
