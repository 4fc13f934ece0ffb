// The compiles ahead of gpu/shader_prewarm.h: a lavapipe device's new
// pipeline is compiled by a worker into Mesa's disk cache, once (a marker
// keeps a second device from compiling it again), and the pass computes what
// it computes without them; the setting is read as its variable says.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "core/errors.h"
#include "gpu/buffer.h"
#include "gpu/compute_pass.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "gpu/shader_prewarm.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;
using gi::gpu::ShaderPrewarm;

// Sets an environment variable for a scope (unset where `value` is null).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) setenv(name, value, 1);
    else unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_) setenv(name_, old_->c_str(), 1);
    else unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

std::size_t files_under(const fs::path& dir) {
  std::size_t n = 0;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) ++n;
  return n;
}

TEST(ShaderPrewarm, TheSettingIsACountOfWorkers) {
  {
    ScopedEnv e("GIHARNESS_SHADER_PREWARM_THREADS", "3");
    EXPECT_EQ(ShaderPrewarm::threads_setting(), 3u);
  }
  {
    ScopedEnv e("GIHARNESS_SHADER_PREWARM_THREADS", "0");
    EXPECT_EQ(ShaderPrewarm::threads_setting(), 0u);
  }
  {
    ScopedEnv e("GIHARNESS_SHADER_PREWARM_THREADS", nullptr);
    EXPECT_GE(ShaderPrewarm::threads_setting(), 1u);
  }
  for (const char* bad : {"two", "-1", "2x", "1000"}) {
    ScopedEnv e("GIHARNESS_SHADER_PREWARM_THREADS", bad);
    try {
      ShaderPrewarm::threads_setting();
      ADD_FAILURE() << "accepted " << bad;
    } catch (const gi::InputError& err) {
      EXPECT_NE(std::string(err.what()).find("GIHARNESS_SHADER_PREWARM_THREADS"), std::string::npos) << err.what();
    }
  }
}

TEST(ShaderPrewarm, APipelineIsCompiledAheadOnceAndComputesTheSame) {
  const fs::path root = fs::path(::testing::TempDir()) / "giharness-prewarm-test";
  fs::remove_all(root);
  const ScopedEnv cache("GIHARNESS_CACHE_DIR", (root / "giharness").c_str());
  const ScopedEnv mesa("MESA_SHADER_CACHE_DIR", (root / "mesa").c_str());
  const ScopedEnv threads("GIHARNESS_SHADER_PREWARM_THREADS", "1");

  gi::gpu::ShaderCompiler compiler(root / "spirv-cache");
  const auto shader = compiler.compile_source(R"(#version 460
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer O { uint o[]; };
void main() { o[gl_GlobalInvocationID.x] = gl_GlobalInvocationID.x * 3u + 1u; }
)", "tests/prewarm.comp", {});
  const std::vector<gi::gpu::DescriptorBinding> storage = {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};

  // Runs the pass on a fresh device; returns the buffer it wrote.
  const auto run = [&](gi::gpu::Device& device) {
    gi::gpu::Buffer out(device, 64 * sizeof(std::uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "prewarm test");
    gi::gpu::ComputePass pass(device, "prewarm_test", shader.spirv, storage);
    pass.bind_buffer(0, out);
    device.submit_and_wait([&](VkCommandBuffer cmd) { pass.dispatch(cmd, 1, 1); });
    std::vector<std::uint32_t> v(64);
    out.download_bytes(v.data(), v.size() * sizeof(std::uint32_t));
    return v;
  };

  std::vector<std::uint32_t> ahead;
  {
    gi::gpu::Device device(std::nullopt, gi::test::test_backend());
    if (!device.prewarm()) GTEST_SKIP() << "no compiles ahead on " << device.info().driver_name;
    ahead = run(device);
  }
  for (std::uint32_t i = 0; i < 64; ++i) ASSERT_EQ(ahead[i], i * 3u + 1u) << i;
  const fs::path markers = root / "giharness" / "prewarmed";
  ASSERT_EQ(files_under(markers), 1u);
  EXPECT_GT(files_under(root / "mesa"), 0u) << "the worker left nothing in Mesa's cache";
  fs::path marker_file;
  for (const auto& e : fs::recursive_directory_iterator(markers))
    if (e.is_regular_file()) marker_file = e.path();
  const auto written = fs::last_write_time(marker_file);

  {
    gi::gpu::Device again(std::nullopt, gi::test::test_backend());
    EXPECT_EQ(run(again), ahead);
  }
  EXPECT_EQ(files_under(markers), 1u);
  EXPECT_EQ(fs::last_write_time(marker_file), written) << "compiled ahead a second time";

  const ScopedEnv off("GIHARNESS_SHADER_PREWARM_THREADS", "0");
  gi::gpu::Device without(std::nullopt, gi::test::test_backend());
  EXPECT_EQ(without.prewarm(), nullptr);
  EXPECT_EQ(run(without), ahead);
}

}  // namespace
