// GPU tests: device bring-up, the shader cache, primary visibility against a
// brute-force CPU ray caster, TLAS rebuild policy, and the determinism of the
// GPU reference path tracer. On the rayquery backend where a device offers
// ray queries (lavapipe), else on bvh (NVIDIA H200, Mesa 22): test_backend().
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "core/errors.h"
#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "gpu/compute_pass.h"
#include "gpu/device.h"
#include "gpu/pipeline_cache.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/bindings.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;
using gi::gpu::ComputePass;
using gi::gpu::DescriptorBinding;
using gi::gpu::Device;
using gi::gpu::PipelineCache;
using gi::gpu::Renderer;
using gi::gpu::RendererOptions;
using gi::gpu::ShaderCompiler;

// One device and one compiler (with a cache under the test temp dir) for the
// whole suite: bringing lavapipe up costs more than most tests.
class Gpu : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    device_ = std::make_unique<Device>(std::nullopt, gi::test::test_backend());
    compiler_ = std::make_unique<ShaderCompiler>(fs::path(::testing::TempDir()) / "giharness-gpu-test-cache");
  }
  static void TearDownTestSuite() {
    compiler_.reset();
    device_.reset();
  }
  static std::unique_ptr<Device> device_;
  static std::unique_ptr<ShaderCompiler> compiler_;
};
std::unique_ptr<Device> Gpu::device_;
std::unique_ptr<ShaderCompiler> Gpu::compiler_;

struct CornellSetup {
  gi::Scene scene = gi::make_cornell_box();
  gi::FlatGeometry geometry = gi::flatten_geometry(scene);
  gi::FlatInstances instances = gi::flatten_instances(scene, geometry);
  std::vector<bool> visible;
  CornellSetup() {
    for (const auto& i : scene.instances) visible.push_back(i.visible);
  }
  gi::FrameConstants frame(std::uint32_t w, std::uint32_t h, std::uint32_t frame_index, std::uint32_t spp,
                           std::uint32_t sample_base, std::uint32_t seed = 7) const {
    gi::FrameConstants f{};
    f.camera = gi::make_gpu_camera(scene.camera, w, h);
    f.previous_camera = f.camera;
    f.resolution_frame = glm::uvec4(w, h, frame_index, seed);
    f.counts = glm::uvec4(std::uint32_t(instances.lights.size()), instances.directional_light_count, spp, sample_base);
    return f;
  }
};

// Möller–Trumbore in double precision, both faces (the TLAS disables culling).
bool intersect(glm::dvec3 o, glm::dvec3 d, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, double& t) {
  const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
  const double det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-14) return false;
  const double inv = 1.0 / det;
  const glm::dvec3 tv = o - p0;
  const double u = glm::dot(tv, pv) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double v = glm::dot(d, qv) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  t = glm::dot(e2, qv) * inv;
  return t > 0.0;
}

struct CpuHit {
  std::uint32_t instance = gi::shader::VISIBILITY_MISS, primitive = gi::shader::VISIBILITY_MISS;
  double t = std::numeric_limits<double>::infinity();
  double second_t = std::numeric_limits<double>::infinity();  // nearest hit on another triangle
};

CpuHit cpu_trace(const CornellSetup& s, glm::vec3 origin, glm::vec3 dir) {
  CpuHit best;
  for (std::uint32_t i = 0; i < s.instances.instances.size(); ++i) {
    if (!s.visible[i]) continue;
    const gi::GpuInstance& inst = s.instances.instances[i];
    const glm::dmat4 m(inst.object_to_world);
    for (std::uint32_t p = 0; p < inst.triangle_count; ++p) {
      glm::dvec3 v[3];
      for (int k = 0; k < 3; ++k)
        v[k] = glm::dvec3(m * glm::dvec4(s.geometry.vertices[inst.first_vertex + s.geometry.indices[inst.first_index + 3 * p + k]].position));
      double t;
      if (!intersect(glm::dvec3(origin), glm::dvec3(dir), v[0], v[1], v[2], t)) continue;
      if (t < best.t) {
        best.second_t = best.t;
        best.t = t;
        best.instance = i;
        best.primitive = p;
      } else if (t < best.second_t) {
        best.second_t = t;
      }
    }
  }
  return best;
}

// The device is the one the suite's probe names (lavapipe when present), its
// description is filled in, and the ray-query entry points are loaded exactly
// when the backend is rayquery.
TEST_F(Gpu, DeviceComesUpAndDescribesItself) {
  const gi::gpu::DeviceInfo& info = device_->info();
  const gi::test::DeviceSupport& support = gi::test::device_support();
  if (support.ray_query) {
    EXPECT_EQ(device_->backend(), gi::gpu::TraceBackend::rayquery);
    EXPECT_NE(device_->khr().cmd_build_acceleration_structures, nullptr);
  } else {
    EXPECT_EQ(device_->backend(), gi::gpu::TraceBackend::bvh);
    EXPECT_EQ(device_->khr().cmd_build_acceleration_structures, nullptr);
    EXPECT_EQ(info.name, support.name);
  }
  EXPECT_EQ(info.ray_query, support.ray_query);
  EXPECT_EQ(info.backend, gi::gpu::backend_name(device_->backend()));
  if (support.lavapipe) {
    EXPECT_NE(info.name.find("llvmpipe"), std::string::npos) << info.name;
    EXPECT_FALSE(info.mesa_version.empty()) << info.driver_info;
  }
  EXPECT_FALSE(info.name.empty());
  EXPECT_FALSE(info.driver_info.empty());
  EXPECT_GT(info.subgroup_size, 0u);
  const nlohmann::json j = info.to_json();
  EXPECT_EQ(j.at("name"), info.name);
  EXPECT_TRUE(j.contains("lp_num_threads"));
  EXPECT_FALSE(Device::list_devices().empty());
}

// The message lists every device, the default one among them.
TEST_F(Gpu, OutOfRangeDeviceIndexListsDevices) {
  try {
    Device d(999);
    FAIL() << "expected DeviceError";
  } catch (const gi::DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("999 is out of range"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(gi::test::device_support().name), std::string::npos) << e.what();
  }
}

// The cache key covers source, includes and defines: the same again is a hit,
// a changed define a miss.
TEST_F(Gpu, ShaderCacheHitsOnSameSourceAndMissesOnChangedDefine) {
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("giharness-cache-test-" + std::to_string(std::random_device{}()));
  fs::remove_all(dir);
  ShaderCompiler compiler(dir);
  const std::string src = R"(#version 460
#include "core/shared/rng.h"
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer O { uint o[]; };
void main() { o[gl_GlobalInvocationID.x] = rng_seed(SEED, 1u, gl_GlobalInvocationID.x, 0u); }
)";
  const auto a = compiler.compile_source(src, "tests/cache_probe.comp", {{"SEED", "1u"}});
  EXPECT_FALSE(a.cache_hit);
  const auto b = compiler.compile_source(src, "tests/cache_probe.comp", {{"SEED", "1u"}});
  EXPECT_TRUE(b.cache_hit);
  EXPECT_EQ(a.spirv, b.spirv);
  const auto c = compiler.compile_source(src, "tests/cache_probe.comp", {{"SEED", "2u"}});
  EXPECT_FALSE(c.cache_hit);
  EXPECT_NE(a.key, c.key);
  EXPECT_EQ(compiler.cache_hits(), 1u);
  EXPECT_EQ(compiler.cache_misses(), 2u);
  // A second compiler on the same directory (a second process) hits too.
  ShaderCompiler again(dir);
  EXPECT_TRUE(again.compile_source(src, "tests/cache_probe.comp", {{"SEED", "2u"}}).cache_hit);
  fs::remove_all(dir);
}

TEST_F(Gpu, CompileErrorNamesTheDefines) {
  ShaderCompiler compiler(fs::path(::testing::TempDir()) / "giharness-gpu-test-cache");
  const std::string src = "#version 460\nlayout(local_size_x = 1) in;\nvoid main() { undeclared_thing = 1; }\n";
  try {
    compiler.compile_source(src, "tests/broken.comp", {{"MY_FLAG", "3"}, {"OTHER", ""}});
    FAIL() << "expected DeviceError";
  } catch (const gi::DeviceError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("MY_FLAG=3"), std::string::npos) << msg;
    EXPECT_NE(msg.find("OTHER"), std::string::npos) << msg;
    EXPECT_NE(msg.find("undeclared_thing"), std::string::npos) << msg;
  }
}

// Every pixel's hit agrees with a brute-force double-precision ray caster:
// same instance and primitive, |Δt|/t < 1e-4. A pixel whose ray passes within
// 1e-6 of a second triangle (a shared edge) may report either.
// Passes of one device with the same SPIR-V, bindings and push constants
// share one pipeline (gpu/pipeline_cache.h): the chains of a run create each
// pipeline once. Another define, binding set or push-constant size is a
// pipeline of its own; a pass destroyed leaves the shared one usable.
TEST_F(Gpu, PassesWithTheSameShaderShareOnePipeline) {
  ShaderCompiler compiler(fs::path(::testing::TempDir()) / "giharness-gpu-test-cache");
  const std::string src = R"(#version 460
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer O { uint o[]; };
void main() { o[gl_GlobalInvocationID.x] = VALUE; }
)";
  const auto one = compiler.compile_source(src, "tests/shared_pipeline.comp", {{"VALUE", "1u"}});
  const auto two = compiler.compile_source(src, "tests/shared_pipeline.comp", {{"VALUE", "2u"}});
  const std::vector<DescriptorBinding> storage = {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
  PipelineCache& cache = device_->pipelines();
  const std::size_t before = cache.size();
  {
    ComputePass a(*device_, "a", one.spirv, storage);
    EXPECT_EQ(cache.size(), before + 1);
    ComputePass b(*device_, "b", one.spirv, storage);  // another chain's pass
    EXPECT_EQ(cache.size(), before + 1);
  }
  ComputePass again(*device_, "again", one.spirv, storage);  // after both are gone
  EXPECT_EQ(cache.size(), before + 1);
  ComputePass other_define(*device_, "c", two.spirv, storage);
  EXPECT_EQ(cache.size(), before + 2);
  ComputePass other_push(*device_, "d", one.spirv, storage, 16);
  EXPECT_EQ(cache.size(), before + 3);
  ComputePass other_binding(*device_, "e", one.spirv, {{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}, {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}});
  EXPECT_EQ(cache.size(), before + 4);
}

TEST_F(Gpu, PrimaryVisibilityMatchesCpuRayCaster) {
  CornellSetup s;
  const std::uint32_t W = 64, H = 64;
  Renderer r(*device_, *compiler_, s.geometry, {W, H, true, false});
  r.update_scene(s.instances, s.visible);
  const gi::FrameConstants f = s.frame(W, H, 0, 1, 0);
  r.render_frame(f);
  const auto vis = r.visibility();
  const auto depth = r.depth();

  int ambiguous = 0;
  for (std::uint32_t y = 0; y < H; ++y)
    for (std::uint32_t x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * W + x;
      const glm::vec3 dir = gi::shader::camera_ray_direction(f.camera, glm::uvec2(x, y), glm::uvec2(W, H));
      const CpuHit c = cpu_trace(s, glm::vec3(f.camera.position), dir);
      if (std::abs(c.second_t - c.t) <= 1e-6 * c.t) {
        ++ambiguous;
        continue;
      }
      ASSERT_EQ(vis[i].x, c.instance) << "pixel " << x << "," << y;
      if (c.instance == gi::shader::VISIBILITY_MISS) continue;
      ASSERT_EQ(vis[i].y, c.primitive) << "pixel " << x << "," << y;
      ASSERT_LT(std::abs(depth[i] - c.t) / c.t, 1e-4) << "pixel " << x << "," << y;
    }
  EXPECT_LT(ambiguous, 8);
  RecordProperty("ambiguous_pixels", ambiguous);

  // The centre looks at the back wall or a block; the box is closed on five
  // sides and the camera looks in through the open front, so nothing misses.
  const std::uint32_t centre = vis[(H / 2) * W + W / 2].x;
  const std::string name = s.scene.instances.at(centre).name;
  EXPECT_TRUE(name == "floor_ceiling_back" || name == "short_block" || name == "tall_block") << name;
  for (std::uint32_t corner : {0u, W - 1, (H - 1) * W, H * W - 1})
    EXPECT_EQ(vis[corner].x == gi::shader::VISIBILITY_MISS,
              cpu_trace(s, glm::vec3(f.camera.position),
                        gi::shader::camera_ray_direction(f.camera, glm::uvec2(corner % W, corner / W),
                                                         glm::uvec2(W, H)))
                      .instance == gi::shader::VISIBILITY_MISS);

  // With a static camera there is no motion; the G-buffer's albedo is the material's.
  const gi::Image motion = r.gbuffer_layer("motion");
  const gi::Image albedo = r.gbuffer_layer("albedo");
  for (std::size_t i = 0; i < motion.size(); ++i) {
    if (vis[i].x == gi::shader::VISIBILITY_MISS) continue;
    EXPECT_LT(glm::length(glm::vec2(motion.pixels[i])), 1e-3f);
    const auto& m = s.instances.materials[s.instances.instances[vis[i].x].material];
    EXPECT_EQ(albedo.pixels[i], glm::vec3(m.base_color_metallic));
  }
}

// Motion vectors: moving the camera to its right makes a static point appear
// further left this frame, so it was further right last frame: motion.x > 0.
TEST_F(Gpu, MotionVectorsFollowThePreviousCamera) {
  CornellSetup s;
  const std::uint32_t W = 32, H = 32;
  Renderer r(*device_, *compiler_, s.geometry, {W, H, true, false});
  r.update_scene(s.instances, s.visible);
  gi::FrameConstants f = s.frame(W, H, 1, 1, 0);
  gi::Camera moved = s.scene.camera;
  const glm::vec3 right = glm::normalize(glm::vec3(f.camera.right));
  moved.position += 0.05f * right;
  moved.target += 0.05f * right;
  f.camera = gi::make_gpu_camera(moved, W, H);
  r.render_frame(f);
  const gi::Image motion = r.gbuffer_layer("motion");
  const gi::Image pos = r.gbuffer_layer("position");
  const auto vis = r.visibility();
  for (std::size_t i = 0; i < motion.size(); ++i) {
    if (vis[i].x == gi::shader::VISIBILITY_MISS) continue;
    ASSERT_EQ(motion.pixels[i].z, 1.0f);
    glm::vec2 expected;
    ASSERT_TRUE(gi::shader::camera_project(f.previous_camera, pos.pixels[i], glm::uvec2(W, H), expected));
    const glm::vec2 current(float(i % W) + 0.5f, float(i / W) + 0.5f);
    EXPECT_NEAR(motion.pixels[i].x, expected.x - current.x, 1e-3f);
    EXPECT_NEAR(motion.pixels[i].y, expected.y - current.y, 1e-3f);
    EXPECT_GT(motion.pixels[i].x, 0.0f);
  }
}

TEST_F(Gpu, TlasRebuildsOnlyWhenATransformOrVisibilityChanges) {
  CornellSetup s;
  Renderer r(*device_, *compiler_, s.geometry, {8, 8, true, false});
  r.update_scene(s.instances, s.visible);
  EXPECT_EQ(r.tlas_builds(), 1u);
  r.update_scene(s.instances, s.visible);
  EXPECT_EQ(r.tlas_builds(), 1u) << "nothing changed";
  const std::uint32_t light = *s.scene.find_instance("light");
  s.instances.instances[light].emissive_scale = glm::vec4(0.0f);
  r.update_scene(s.instances, s.visible);
  EXPECT_EQ(r.tlas_builds(), 1u) << "emission is not geometry";
  const std::uint32_t tall = *s.scene.find_instance("tall_block");
  s.instances.instances[tall].object_to_world =
      glm::translate(glm::mat4(1.0f), glm::vec3(0.01f, 0.0f, 0.0f)) * s.instances.instances[tall].object_to_world;
  r.update_scene(s.instances, s.visible);
  EXPECT_EQ(r.tlas_builds(), 2u) << "a transform changed";
  s.visible[tall] = false;
  r.update_scene(s.instances, s.visible);
  EXPECT_EQ(r.tlas_builds(), 3u) << "visibility changed";
  s.instances.instances[tall].object_to_world = glm::mat4(2.0f);
  r.update_scene(s.instances, s.visible);
  EXPECT_EQ(r.tlas_builds(), 3u) << "a hidden instance moved";
  r.render_frame(s.frame(8, 8, 0, 1, 0));
  for (const glm::uvec2 v : r.visibility()) EXPECT_NE(v.x, tall);
}

// 16 frames of 1 spp at 32x32 on a fresh renderer (sample base = frame index).
std::unique_ptr<Renderer> run_reference(Device& device, ShaderCompiler& compiler, const CornellSetup& s) {
  const std::uint32_t W = 32, H = 32;
  auto r = std::make_unique<Renderer>(device, compiler, s.geometry, RendererOptions{W, H, true, true});
  r->update_scene(s.instances, s.visible);
  for (std::uint32_t f = 0; f < 16; ++f) r->render_frame(s.frame(W, H, f, 1, f));
  return r;
}

// Two runs of 16 frames give the same bits; the mean is finite everywhere and
// positive on the lit walls.
TEST_F(Gpu, ReferenceIsBitIdenticalAcrossRunsAndLitWallsArePositive) {
  CornellSetup s;
  const std::vector<glm::vec4> a1 = run_reference(*device_, *compiler_, s)->reference_sums(0);
  const std::vector<glm::vec4> b1 = run_reference(*device_, *compiler_, s)->reference_sums(1);
  const std::unique_ptr<Renderer> r = run_reference(*device_, *compiler_, s);
  const std::vector<glm::vec4> a2 = r->reference_sums(0), b2 = r->reference_sums(1);
  ASSERT_EQ(a1.size(), a2.size());
  EXPECT_EQ(std::memcmp(a1.data(), a2.data(), a1.size() * sizeof(glm::vec4)), 0);
  EXPECT_EQ(std::memcmp(b1.data(), b2.data(), b1.size() * sizeof(glm::vec4)), 0);
  for (std::size_t i = 0; i < a2.size(); ++i) {
    EXPECT_EQ(a2[i].w, 8.0f);  // even sample indices 0, 2, ..., 14
    EXPECT_EQ(b2[i].w, 8.0f);
  }
  EXPECT_EQ(r->reference_nonfinite_samples(), 0u);

  const gi::Image mean = r->reference_mean();
  const auto vis = r->visibility();
  const std::uint32_t red = *s.scene.find_instance("red_wall"), green = *s.scene.find_instance("green_wall");
  int wall_pixels = 0;
  glm::vec3 red_sum(0.0f);
  for (std::size_t i = 0; i < mean.size(); ++i) {
    const glm::vec3 c = mean.pixels[i];
    ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) << i;
    if (vis[i].x == red || vis[i].x == green) {
      ++wall_pixels;
      EXPECT_GT(gi::shader::luminance(c), 0.0f) << "pixel " << i;
    }
    if (vis[i].x == red) red_sum += c;
  }
  EXPECT_GT(wall_pixels, 20);
  EXPECT_GT(red_sum.x, red_sum.y) << "the red wall reflects red";
}

}  // namespace
