// temporal.motion_vectors: what "object" (Bevy's prepass motion vectors,
// v0.18.0:bevy_pbr/src/prepass/prepass.wgsl:158-164,197-205, read by
// v0.18.0:realtime/restir_di.wgsl:156-157) changes against "camera" (the
// harness's earlier model: the previous camera alone). The tall block of the
// Cornell box moves up 8 cm between two frames of a still camera; its
// G-buffer's motion vectors, and the temporal source pixel the DI and GI
// passes would reuse (temporal_source_pixel, pixel_dissimilar: the shared
// code the shaders run), are read back and judged on the CPU.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "core/shared/restir_di.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/gbuffer.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;
using gi::gpu::MotionVectors;

class MotionVectorsFidelity : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    device_ = std::make_unique<gi::gpu::Device>(std::nullopt, gi::test::test_backend());
    compiler_ = std::make_unique<gi::gpu::ShaderCompiler>(fs::path(::testing::TempDir()) / "giharness-motion-test-cache");
  }
  static void TearDownTestSuite() {
    compiler_.reset();
    device_.reset();
  }
  static std::unique_ptr<gi::gpu::Device> device_;
  static std::unique_ptr<gi::gpu::ShaderCompiler> compiler_;
};
std::unique_ptr<gi::gpu::Device> MotionVectorsFidelity::device_;
std::unique_ptr<gi::gpu::ShaderCompiler> MotionVectorsFidelity::compiler_;

constexpr std::uint32_t W = 64, H = 64;
const glm::vec3 kMove(0.0f, 0.08f, 0.0f);  // a quarter of the tall block's height, about 6 pixels

// One frame's G-buffer as the test reads it.
struct Frame {
  std::vector<glm::uvec2> visibility;
  gi::Image position, normal, motion;
};

struct Measured {
  std::size_t block_pixels = 0;
  std::size_t motion_is_the_objects = 0;  // the motion vector is the block's own screen motion
  std::size_t motion_is_zero = 0;
  std::size_t accepted = 0;      // the temporal source passes pixel_dissimilar
  std::size_t own_history = 0;   // ... and holds the same point of the block last frame
};

Measured measure(gi::gpu::Device& device, gi::gpu::ShaderCompiler& compiler, MotionVectors mode) {
  const gi::Scene scene = gi::make_cornell_box();
  const gi::FlatGeometry geometry = gi::flatten_geometry(scene);
  gi::FlatInstances flat = gi::flatten_instances(scene, geometry);
  std::vector<bool> visible;
  for (const auto& i : scene.instances) visible.push_back(i.visible);
  const std::uint32_t tall = *scene.find_instance("tall_block");

  gi::gpu::RendererOptions options{W, H, true, false};
  options.motion_vectors = mode;
  gi::gpu::Renderer r(device, compiler, geometry, options);
  gi::FrameConstants f{};
  f.camera = gi::make_gpu_camera(scene.camera, W, H);
  f.previous_camera = f.camera;
  f.counts = glm::uvec4(std::uint32_t(flat.lights.size()), flat.directional_light_count, 1, 0);
  auto render = [&](std::uint32_t frame) {
    f.resolution_frame = glm::uvec4(W, H, frame, 7);
    r.update_scene(flat, visible);
    r.render_frame(f);
    return Frame{r.visibility(), r.gbuffer_layer("position"), r.gbuffer_layer("normal"), r.gbuffer_layer("motion")};
  };
  const Frame before = render(0);
  // Frame 1: the block 8 cm higher; its previous transform is frame 0's (as
  // apply_events sets Instance::previous_transform and flatten_instances copies it).
  const glm::mat4 was = flat.instances[tall].object_to_world;
  flat.instances[tall].object_to_world = glm::translate(glm::mat4(1.0f), kMove) * was;
  flat.instances[tall].normal_to_world = glm::transpose(glm::inverse(flat.instances[tall].object_to_world));
  flat.previous_object_to_world[tall] = was;
  const Frame now = render(1);

  const glm::vec3 eye(f.camera.position);
  const glm::vec3 forward = glm::normalize(glm::vec3(scene.camera.target - scene.camera.position));
  Measured m;
  for (std::uint32_t y = 0; y < H; ++y)
    for (std::uint32_t x = 0; x < W; ++x) {
      const std::size_t i = std::size_t(y) * W + x;
      if (now.visibility[i].x != tall) continue;
      ++m.block_pixels;
      const glm::vec3 p = now.position.pixels[i];
      const glm::vec3 mv = now.motion.pixels[i];
      // Where this point of the block was last frame, on last frame's screen.
      glm::vec2 was_at;
      EXPECT_TRUE(gi::shader::camera_project(f.previous_camera, p - kMove, glm::uvec2(W, H), was_at));
      const glm::vec2 object_motion = was_at - glm::vec2(float(x) + 0.5f, float(y) + 0.5f);
      if (mv.z == 1.0f && glm::length(glm::vec2(mv) - object_motion) < 1e-2f) ++m.motion_is_the_objects;
      if (mv.z == 1.0f && glm::length(glm::vec2(mv)) < 1e-3f) ++m.motion_is_zero;
      glm::ivec2 q;
      if (!gi::shader::temporal_source_pixel(glm::uvec2(x, y), glm::vec4(mv, 0.0f), glm::uvec2(W, H), false, q))
        continue;
      const std::size_t j = std::size_t(q.y) * W + q.x;
      if (before.visibility[j].x == gi::shader::VISIBILITY_MISS) continue;
      const float view_z = glm::dot(p - eye, forward);
      // The 0.18 profile's restir_di.dissimilar_plane_tolerance and dissimilar_normal_min_dot.
      if (gi::shader::pixel_dissimilar(view_z, p, before.position.pixels[j], now.normal.pixels[i],
                                       before.normal.pixels[j], 0.003f, 0.906f))
        continue;
      ++m.accepted;
      // Half the move: a pixel's footprint here is about 1.3 cm.
      if (glm::length(before.position.pixels[j] + kMove - p) < 0.5f * glm::length(kMove)) ++m.own_history;
    }
  return m;
}

}  // namespace

// Under "object" every pixel of the moving block carries the block's own
// screen motion, and temporal reuse finds the same point of the block last
// frame: reuse is accepted and the history is the surface's own. Under
// "camera" (a still camera) the motion is zero: the pixel reads its own last
// frame, where the block's top band saw the back wall (refused by
// pixel_dissimilar) and the rest saw the block 8 cm lower (accepted: the
// same plane, but another point of it).
TEST_F(MotionVectorsFidelity, AMovingObjectsPixelsReuseTheirOwnHistoryOnlyUnderObjectMotion) {
  const Measured object = measure(*device_, *compiler_, MotionVectors::object);
  const Measured camera = measure(*device_, *compiler_, MotionVectors::camera);
  ASSERT_GT(object.block_pixels, 300u);  // about 14 x 26 pixels at 64 x 64
  ASSERT_EQ(object.block_pixels, camera.block_pixels);
  const double n = double(object.block_pixels);
  SCOPED_TRACE(testing::Message() << "object: motion " << object.motion_is_the_objects << ", accepted "
                                  << object.accepted << ", own " << object.own_history << "; camera: zero "
                                  << camera.motion_is_zero << ", accepted " << camera.accepted << ", own "
                                  << camera.own_history << " of " << n);
  EXPECT_EQ(object.motion_is_the_objects, object.block_pixels);
  EXPECT_EQ(object.motion_is_zero, 0u);
  EXPECT_EQ(camera.motion_is_zero, camera.block_pixels);
  // Object motion: all but the pixels whose rounded source lands across the
  // block's vertical edge.
  EXPECT_GE(object.own_history / n, 0.95);
  EXPECT_EQ(object.own_history, object.accepted);
  // Camera motion: no pixel gets its own point's history; the top band
  // (8 cm of 33) is refused.
  EXPECT_EQ(camera.own_history, 0u);
  EXPECT_LE(camera.accepted / n, 0.85);
}
