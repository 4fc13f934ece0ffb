// The Cornell box rendered with the world cache and its debug view on (every
// primary surface queries the cache, pixel-rooted, as Bevy's
// VISUALIZE_WORLD_CACHE), no GI and no reference: what the world-cache tests
// read cells and irradiance from (tests/world_cache_test.cpp,
// tests/world_cache_fidelity_test.cpp).
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "core/cache_root.h"
#include "core/scene_flatten.h"
#include "core/scenes/cornell_box.h"
#include "gpu/device.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "tests/test_support.h"

namespace gi::test {

class CornellCacheView {
 public:
  CornellCacheView(std::uint32_t width, std::uint32_t height, gpu::WorldCacheSettings cache)
      : width_(width),
        height_(height),
        scene_(make_cornell_box()),
        geometry_(flatten_geometry(scene_)),
        flat_(flatten_instances(scene_, geometry_)),
        device_(std::nullopt, test_backend()),
        compiler_(cache_root()),
        renderer_(device_, compiler_, geometry_, options(width, height, cache)) {
    renderer_.update_scene(flat_, std::vector<bool>(scene_.instances.size(), true));
  }

  // Frame `frame` from the scene's (static) camera, seed 7.
  void render(std::uint32_t frame) {
    FrameConstants c{};
    c.camera = c.previous_camera = camera();
    c.resolution_frame = glm::uvec4(width_, height_, frame, 7u);
    c.counts = glm::uvec4(static_cast<std::uint32_t>(flat_.lights.size()), flat_.directional_light_count, 1u, frame);
    renderer_.render_frame(c);
  }

  GpuCamera camera() const { return make_gpu_camera(scene_.camera, width_, height_); }
  const Scene& scene() const { return scene_; }
  const FlatGeometry& geometry() const { return geometry_; }
  const FlatInstances& flat() const { return flat_; }
  gpu::Renderer& renderer() { return renderer_; }

 private:
  static gpu::RendererOptions options(std::uint32_t w, std::uint32_t h, gpu::WorldCacheSettings cache) {
    gpu::RendererOptions o;
    o.width = w;
    o.height = h;
    o.reference = false;
    cache.view = true;
    // No DI here, so no light tiles: the cache draws its own candidates.
    cache.tile_candidates = false;
    o.world_cache = cache;
    return o;
  }

  std::uint32_t width_, height_;
  Scene scene_;
  FlatGeometry geometry_;
  FlatInstances flat_;
  gpu::Device device_;
  gpu::ShaderCompiler compiler_;
  gpu::Renderer renderer_;
};

}  // namespace gi::test
