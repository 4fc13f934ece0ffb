// Observation on the GPU: the buffer hash computed by
// buffer_hash.comp equals its CPU twin (core/shared/word_hash.h) on the same
// bytes, and the frame output pass makes the image the CPU made before, bit
// for bit, with the measures the CPU took of it.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "core/cache_root.h"
#include "core/errors.h"
#include "core/metrics.h"
#include "core/profile.h"
#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "core/shared/word_hash.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "gpu/realtime_settings.h"
#include "tests/test_support.h"

namespace gi {
namespace {

std::vector<std::uint32_t> random_words(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint32_t> w(n);
  for (auto& x : w) x = rng();
  return w;
}

std::string cpu_hash(const std::vector<std::uint32_t>& w, std::size_t first = 0, std::size_t n = SIZE_MAX) {
  n = std::min(n, w.size() - first);
  return shader::word_hash_bytes(w.data() + first, n * 4);
}

TEST(WordHash, EveryWordAndItsPlaceCount) {
  std::vector<std::uint32_t> w = random_words(1000, 1);
  const std::string h = cpu_hash(w);
  EXPECT_EQ(h.size(), 16u);
  std::vector<std::uint32_t> flipped = w;
  flipped[517] ^= 1u << 20;
  EXPECT_NE(cpu_hash(flipped), h);
  // Two whole chunks swapped: same chunk hashes, other seeds.
  std::vector<std::uint32_t> swapped = w;
  std::swap_ranges(swapped.begin(), swapped.begin() + 16, swapped.begin() + 32);
  EXPECT_NE(cpu_hash(swapped), h);
  // Trailing zero words are not free.
  std::vector<std::uint32_t> longer = w;
  longer.push_back(0);
  EXPECT_NE(cpu_hash(longer), h);
  EXPECT_NE(shader::word_hash_bytes(nullptr, 0), cpu_hash({0u}));
}

class BufferHashGpu : public ::testing::Test {
 protected:
  void SetUp() override {
    device_.emplace(std::nullopt, test::test_backend());
    compiler_.emplace(cache_root());
  }
  std::optional<gpu::Device> device_;
  std::optional<gpu::ShaderCompiler> compiler_;
};

// The test observation on the GPU stands on: the GPU's hash of a buffer is the CPU's hash of
// the same bytes, at sizes around the chunk (16 words) and the workgroup
// (64 chunks), for a range at an offset, and in either buffer memory mode.
TEST_F(BufferHashGpu, GpuHashIsTheCpuHashOfTheSameBytes) {
  const std::vector<std::uint32_t> w = random_words((1u << 20) + 37, 2);
  gpu::Buffer buffer(*device_, w.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "hash test");
  buffer.upload(w);
  gpu::BufferHash hash(*device_, *compiler_);
  std::vector<gpu::HashRange> ranges;
  std::vector<std::string> expected;
  for (std::size_t n : {0ul, 1ul, 15ul, 16ul, 17ul, 1023ul, 1024ul, 1025ul, 65537ul, w.size()}) {
    ranges.push_back({&buffer, n * 4});
    expected.push_back(cpu_hash(w, 0, n));
  }
  ranges.push_back({&buffer, 4000 * 4, 123 * 4});
  expected.push_back(cpu_hash(w, 123, 4000));
  EXPECT_EQ(hash.hash_now(ranges), expected);
  EXPECT_THROW(hash.hash_now({{&buffer, 6}}), DeviceError);  // not whole words
}

// The realtime output (chain A's DI + GI + specular) and the reference mean
// made on the GPU have the bits the CPU sum had (Renderer::realtime_frame,
// reference_mean); the measures are the CPU's figures of that image (sums
// in another order: equal to 1e-12); the image hash is the CPU hash of it.
void expect_measures_of(const gpu::FrameMeasures& m, const Image& image) {
  EXPECT_NEAR(m.output_luminance, mean_luminance(image), 1e-12 * std::max(1.0, mean_luminance(image)));
  EXPECT_EQ(m.nonfinite_components, count_nonfinite(image));
  EXPECT_EQ(m.image_hash, shader::word_hash_bytes(image.pixels.data(), image.pixels.size() * sizeof(glm::vec3)));
}

bool same_bits(const Image& a, const Image& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(glm::vec3)) == 0;
}

struct CornellRun {
  Scene scene = make_cornell_box();
  FlatGeometry geometry = flatten_geometry(scene);
  FlatInstances flat = flatten_instances(scene, geometry);
  FrameConstants frame(std::uint32_t w, std::uint32_t h, std::uint32_t f) const {
    FrameConstants c{};
    c.camera = c.previous_camera = make_gpu_camera(scene.camera, w, h);
    c.resolution_frame = glm::uvec4(w, h, f, 7u);
    c.counts = glm::uvec4(std::uint32_t(flat.lights.size()), flat.directional_light_count, 2u, f * 2u);
    return c;
  }
};

TEST_F(BufferHashGpu, RealtimeOutputHasTheCpuSumsBitsAndMeasures) {
  CornellRun s;
  const Profile profile = load_profile("solari-0.18");
  const std::uint32_t w = 48, h = 40;
  gpu::RendererOptions o;
  o.width = w;
  o.height = h;
  o.reference = false;
  o.frame_output = true;
  o.di = di_settings_from_profile(profile, s.flat, 1, true);
  gpu::WorldCacheSettings cache = world_cache_settings_from_profile(profile);
  cache.cells = 1u << 14;
  o.world_cache = cache;
  o.gi = gi_settings_from_profile(profile, 1);
  gpu::Renderer r(*device_, *compiler_, s.geometry, o);
  r.update_scene(s.flat, std::vector<bool>(s.scene.instances.size(), true));
  gpu::FrameOutput& out = r.frame_output();
  out.restart_noise();
  out.set_accumulate_noise(true);
  std::map<std::string, std::vector<glm::dvec3>> sum, sum_sq;
  for (std::uint32_t f = 0; f < 4; ++f) {
    r.render_frame(s.frame(w, h, f));
    const Image cpu = r.realtime_frame(0);
    const Image gpu = out.image();
    ASSERT_TRUE(same_bits(gpu, cpu)) << "frame " << f;
    const gpu::FrameMeasures m = out.measures();
    expect_measures_of(m, cpu);
    EXPECT_NEAR(m.di_luminance, mean_luminance(r.di().frame(0)), 1e-12);
    EXPECT_NEAR(m.gi_luminance, mean_luminance(r.gi().gi_frame(0)), 1e-12);
    EXPECT_NEAR(m.specular_luminance, mean_luminance(r.gi().specular_frame(0)), 1e-12);
    // The temporal-noise sums, as replay/signal_noise.cpp added them on the CPU.
    const std::map<std::string, Image> signals = {
        {"output", cpu}, {"di", r.di().frame(0)}, {"gi", r.gi().gi_frame(0)}, {"specular", r.gi().specular_frame(0)}};
    for (const auto& [name, image] : signals) {
      sum[name].resize(image.size());
      sum_sq[name].resize(image.size());
      for (std::size_t i = 0; i < image.size(); ++i) {
        const glm::dvec3 x(image.pixels[i]);
        sum[name][i] += x;
        sum_sq[name][i] += x * x;
      }
    }
  }
  const auto gpu_sums = out.noise_sums();
  ASSERT_EQ(gpu_sums.size(), 4u);
  for (const auto& [name, sums] : gpu_sums) {
    EXPECT_TRUE(sums.sum == sum[name]) << name;
    EXPECT_TRUE(sums.sum_sq == sum_sq[name]) << name;
  }
}

TEST_F(BufferHashGpu, ReferenceOutputIsTheHalvesMeanBitForBit) {
  CornellRun s;
  const std::uint32_t w = 40, h = 32;
  gpu::RendererOptions o;
  o.width = w;
  o.height = h;
  o.frame_output = true;
  gpu::Renderer r(*device_, *compiler_, s.geometry, o);
  r.update_scene(s.flat, std::vector<bool>(s.scene.instances.size(), true));
  for (std::uint32_t f = 0; f < 2; ++f) {
    r.render_frame(s.frame(w, h, f));
    const Image cpu = r.reference_mean();
    ASSERT_TRUE(same_bits(r.frame_output().image(), cpu)) << "frame " << f;
    expect_measures_of(r.frame_output().measures(), cpu);
  }
  EXPECT_THROW(r.frame_output().restart_noise(), DeviceError);
}

}  // namespace
}  // namespace gi
