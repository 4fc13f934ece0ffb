#include "gpu/passes/di_pipeline.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include "core/shared/light_tiles.h"
#include "core/shared/reservoir.h"
#include "core/shared/restir_di.h"
#include "gpu/compute_pass.h"

namespace gi::gpu {

using namespace gi::shader;

static_assert(sizeof(PackedLightSample) == 24, "light-tile samples are 24 bytes (docs/design.md §3 step 4)");
static_assert(sizeof(LightSample) == 16);
static_assert(sizeof(DiReservoir) == 32);
static_assert(sizeof(DiSurface) == 48);

namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

// A light's identity across frames: its instance, or (directional) its index
// among the directional lights with a flag bit.
std::vector<std::uint32_t> light_keys(const FlatInstances& scene) {
  std::vector<std::uint32_t> keys;
  for (std::uint32_t i = 0; i < scene.lights.size(); ++i)
    keys.push_back(scene.lights[i].kind == LIGHT_KIND_DIRECTIONAL ? (0x80000000u | i) : scene.lights[i].instance);
  return keys;
}

}  // namespace

std::uint32_t light_tile_samples_for_scene(const FlatInstances& scene, std::uint32_t configured,
                                           std::uint32_t initial_samples) {
  std::uint64_t emitters = 0;
  for (const GpuLight& l : scene.lights) emitters += l.kind == LIGHT_KIND_DIRECTIONAL ? 1 : l.triangle_count;
  const std::uint64_t wanted = std::max<std::uint64_t>(initial_samples, 64 * emitters);
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(configured, std::bit_ceil(wanted)));
}

DiPipeline::DiPipeline(Device& device, ShaderCompiler& compiler, const DiSettings& s, std::uint32_t width,
                       std::uint32_t height)
    : device_(device),
      settings_(s),
      width_(width),
      height_(height),
      tile_samples_(device, std::size_t(s.chains) * s.tile_count * s.samples_per_tile * sizeof(LightSample), kStorage,
                    "light tile samples"),
      tile_packed_(device, std::size_t(s.chains) * s.tile_count * s.samples_per_tile * sizeof(PackedLightSample),
                   kStorage, "light tiles packed"),
      stored_(device, s.chains * pixels() * sizeof(DiReservoir), kStorage, "DI stored reservoirs"),
      mid_(device, s.chains * pixels() * sizeof(DiReservoir), kStorage, "DI mid reservoirs"),
      surfaces_(device, pixels() * sizeof(DiSurface), kStorage, "DI surfaces"),
      translation_(device, 16, kStorage, "DI light translation", BufferMemory::host_write),
      output_(device, s.chains * pixels() * sizeof(glm::vec4), kStorage, "DI output"),
      accumulation_(device, s.chains * pixels() * sizeof(glm::vec4), kStorage, "DI accumulation"),
      light_tiles_(device, compiler, s),
      initial_temporal_(device, compiler, s),
      spatial_shade_(device, compiler, s) {
  stored_.fill_zero();
  mid_.fill_zero();
  surfaces_.fill_zero();
  translation_.fill_zero();
  output_.fill_zero();
  accumulation_.fill_zero();
}

void DiPipeline::update_lights(const FlatInstances& scene) {
  const std::vector<std::uint32_t> keys = light_keys(scene);
  std::vector<std::uint32_t> table(previous_keys_.size(), LIGHT_ID_GONE);
  for (std::size_t old = 0; old < previous_keys_.size(); ++old) {
    auto it = std::find(keys.begin(), keys.end(), previous_keys_[old]);
    if (it != keys.end()) table[old] = static_cast<std::uint32_t>(it - keys.begin());
  }
  upload_translation(table);
  previous_keys_ = keys;
  lights_updated_ = true;
}

void DiPipeline::upload_translation(const std::vector<std::uint32_t>& table) {
  const VkDeviceSize bytes = std::max<std::size_t>(table.size(), 1) * sizeof(std::uint32_t);
  if (translation_.size() < bytes) {
    translation_ = Buffer(device_, bytes, kStorage, "DI light translation", BufferMemory::host_write);
    if (bound_) bind(bound_scene_, *bound_gbuffer_);  // the descriptors named the old buffer
  }
  if (!table.empty()) translation_.upload(table);
  previous_light_count_ = static_cast<std::uint32_t>(table.size());
}

void DiPipeline::bind(const SceneResources& scene, const Buffer& gbuffer) {
  bound_ = true;
  bound_scene_ = scene;
  bound_gbuffer_ = &gbuffer;
  DiBuffers b{&gbuffer, &tile_samples_, &tile_packed_, &stored_, &mid_, &surfaces_, &translation_, &output_,
              &accumulation_};
  light_tiles_.bind(scene, b);
  initial_temporal_.bind(scene, b);
  spatial_shade_.bind(scene, b);
}

void DiPipeline::record(VkCommandBuffer cmd, GpuTimer& timer, bool accumulate) {
  if (!lights_updated_) {
    // The light list did not change since last frame: ids map to themselves.
    std::vector<std::uint32_t> identity(previous_keys_.size());
    for (std::uint32_t i = 0; i < identity.size(); ++i) identity[i] = i;
    upload_translation(identity);
  }
  DiPushConstants push{};
  push.chain_count = settings_.chains;
  push.previous_light_count = previous_light_count_;
  push.history_valid = history_valid_ ? 1u : 0u;
  push.accumulate = accumulate ? 1u : 0u;
  timer.begin(cmd, "light_tiles");
  light_tiles_.record(cmd);
  timer.end(cmd);
  compute_barrier(cmd);
  timer.begin(cmd, "di_initial_temporal");
  initial_temporal_.record(cmd, width_, height_, push);
  timer.end(cmd);
  compute_barrier(cmd);
  timer.begin(cmd, "di_spatial_shade");
  spatial_shade_.record(cmd, width_, height_, push);
  timer.end(cmd);
  compute_barrier(cmd);
  history_valid_ = true;
  lights_updated_ = false;
}

void DiPipeline::reset_accumulation() { accumulation_.fill_zero(); }

void DiPipeline::list_state(StateList& out) {
  const std::uint64_t c = settings_.chains, h = height_, w = width_;
  const std::uint64_t tiles = settings_.tile_count, samples = settings_.samples_per_tile;
  // The translation table is not listed: record() writes it (mapped) from the host
  // state every frame before any pass reads it.
  out.push_back({"di/light_tile_samples", &tile_samples_, "<u4", {c, tiles, samples, 4}, "LightSample (core/shared/light_tiles.h)"});
  out.push_back({"di/light_tiles_packed", &tile_packed_, "<u4", {c, tiles, samples, 6}, "PackedLightSample (core/shared/light_tiles.h)"});
  out.push_back({"di/stored_reservoirs", &stored_, "<u4", {c, h, w, 8}, "DiReservoir (core/shared/reservoir.h)"});
  out.push_back({"di/mid_reservoirs", &mid_, "<u4", {c, h, w, 8}, "DiReservoir (core/shared/reservoir.h)"});
  out.push_back({"di/surfaces", &surfaces_, "<f4", {h, w, 12}, "DiSurface (core/shared/restir_di.h)"});
  out.push_back({"di/output", &output_, "<f4", {c, h, w, 4}, "rgb, w 1 on a hit"});
  out.push_back({"di/accumulation", &accumulation_, "<f4", {c, h, w, 4}, "rgb sum, w frames"});
}

void DiPipeline::save_host_state(HostState& out) const {
  out.push_back({"di/previous_light_keys", previous_keys_});
  out.push_back({"di/flags", {previous_light_count_, history_valid_ ? 1u : 0u, lights_updated_ ? 1u : 0u}});
}

void DiPipeline::restore_host_state(const HostState& in) {
  const HostStateEntry* keys = find_host_state(in, "di/previous_light_keys");
  const HostStateEntry* flags = find_host_state(in, "di/flags");
  if (!keys || !flags || flags->words.size() != 3)
    throw std::invalid_argument("DiPipeline::restore_host_state: di/previous_light_keys and di/flags (3 words) needed");
  previous_keys_ = keys->words;
  previous_light_count_ = flags->words[0];
  history_valid_ = flags->words[1] != 0;
  lights_updated_ = flags->words[2] != 0;
}

// Each reads back only the chain's own slice of the buffer.
Image DiPipeline::frame(std::uint32_t chain) const {
  const auto texels = output_.download<glm::vec4>(pixels(), chain * pixels());
  Image img(width_, height_);
  for (std::size_t i = 0; i < pixels(); ++i) img.pixels[i] = glm::vec3(texels[i]);
  return img;
}

std::vector<shader::LightSample> DiPipeline::tile_samples(std::uint32_t chain) const {
  const std::size_t n = std::size_t(settings_.tile_count) * settings_.samples_per_tile;
  return tile_samples_.download<shader::LightSample>(n, chain * n);
}

Image DiPipeline::mean(std::uint32_t chain) const {
  const auto sums = accumulation_.download<glm::vec4>(pixels(), chain * pixels());
  Image img(width_, height_);
  for (std::size_t i = 0; i < pixels(); ++i) {
    const glm::vec4 s = sums[i];
    img.pixels[i] = s.w > 0.0f ? glm::vec3(s) / s.w : glm::vec3(0.0f);
  }
  return img;
}

std::uint32_t DiPipeline::accumulated_frames(std::uint32_t chain) const {
  return static_cast<std::uint32_t>(accumulation_.download<glm::vec4>(1, chain * pixels())[0].w);
}

}  // namespace gi::gpu
