// The realtime DI signal (docs/design.md §3 steps 4 and 6) as the Renderer drives it:
// owns the light tiles, the reservoirs, last frame's surfaces, the light-id
// translation and the outputs of `chains` independent DI chains (each its own
// light tiles, reservoirs and random streams, so that two chains give an
// honest noise estimate of each other despite temporal reuse).
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "core/scene_flatten.h"
#include "core/shared/reservoir.h"
#include "gpu/buffer.h"
#include "gpu/passes/light_tiles.h"
#include "gpu/passes/restir_di.h"
#include "gpu/state_buffers.h"
#include "gpu/timer.h"

namespace gi::gpu {

class DiPipeline {
 public:
  DiPipeline(Device& device, ShaderCompiler& compiler, const DiSettings& settings, std::uint32_t width,
             std::uint32_t height);

  // Light ids of reservoirs from last frame are translated to this frame's
  // list (an instance's light keeps its identity; a light gone is dropped).
  void update_lights(const FlatInstances& scene);
  void bind(const SceneResources& scene, const Buffer& gbuffer);
  // The packed light tiles (chain 0 first), which the world cache's update reads.
  const Buffer& tile_packed() const { return tile_packed_; }
  const Buffer& output_buffer() const { return output_; }  // vec4 per pixel, chain-major
  // Records the three passes, each timed ("light_tiles", "di_initial_temporal",
  // "di_spatial_shade"), with barriers. accumulate: add this frame to the sums.
  void record(VkCommandBuffer cmd, GpuTimer& timer, bool accumulate);
  // Zeroes the per-window sums (the reservoirs are kept: that is temporal reuse).
  void reset_accumulation();

  Image frame(std::uint32_t chain) const;  // this frame's DI
  Image mean(std::uint32_t chain) const;   // sum / frames over the window
  std::uint32_t accumulated_frames(std::uint32_t chain) const;
  // This frame's light-tile samples of one chain, tile-major
  // (settings().tile_count × samples_per_tile).
  std::vector<shader::LightSample> tile_samples(std::uint32_t chain) const;
  const DiSettings& settings() const { return settings_; }

  // Captures and replay (gpu/state_buffers.h): every buffer a frame writes or
  // carries to the next, and the host-side state. Restore after
  // update_lights() of the captured frame's scene (it resets the keys).
  void list_state(StateList& out);
  void save_host_state(HostState& out) const;
  void restore_host_state(const HostState& in);

 private:
  void upload_translation(const std::vector<std::uint32_t>& table);
  std::size_t pixels() const { return std::size_t(width_) * height_; }

  Device& device_;
  DiSettings settings_;
  std::uint32_t width_, height_;
  Buffer tile_samples_, tile_packed_, stored_, mid_, surfaces_, translation_, output_, accumulation_;
  LightTiles light_tiles_;
  DiInitialTemporal initial_temporal_;
  DiSpatialShade spatial_shade_;
  std::vector<std::uint32_t> previous_keys_;  // light identity per id, last frame
  std::uint32_t previous_light_count_ = 0;
  bool history_valid_ = false;
  bool lights_updated_ = false;
  bool bound_ = false;
  SceneResources bound_scene_;
  const Buffer* bound_gbuffer_ = nullptr;  // update_lights since the last record: its table holds
};

// Samples per tile for a scene (profile light_tiles.size_to_scene): a scene
// with few emissive triangles needs fewer distinct presampled points;
// max(initial_samples, 64 × emissive triangles + directional lights) rounded
// up to a power of two, at most `configured`.
std::uint32_t light_tile_samples_for_scene(const FlatInstances& scene, std::uint32_t configured,
                                           std::uint32_t initial_samples);

}  // namespace gi::gpu
