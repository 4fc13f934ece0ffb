#include "gpu/passes/gi_pipeline.h"

#include <cstring>
#include <stdexcept>

#include "core/shared/restir_gi.h"
#include "core/shared/rng.h"

namespace gi::gpu {

using namespace gi::shader;

static_assert(sizeof(GiReservoir) == 48);
static_assert(sizeof(GiSurface) == 48);
static_assert(sizeof(GiStats) == 40 * 4);
static_assert(sizeof(GiCounters) == 4 * 4);

namespace {
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
}

GiPipeline::GiPipeline(Device& device, ShaderCompiler& compiler, const GiSettings& s, std::uint32_t width,
                       std::uint32_t height)
    : settings_(s),
      width_(width),
      height_(height),
      stored_(device, s.chains * pixels() * sizeof(GiReservoir), kStorage, "GI stored reservoirs"),
      mid_(device, s.chains * pixels() * sizeof(GiReservoir), kStorage, "GI mid reservoirs"),
      surfaces_(device, pixels() * sizeof(GiSurface), kStorage, "GI surfaces"),
      output_(device, s.chains * pixels() * sizeof(glm::vec4), kStorage, "GI output"),
      accumulation_(device, s.chains * pixels() * sizeof(glm::vec4), kStorage, "GI accumulation"),
      stats_(device, sizeof(GiStats), kStorage, "GI statistics"),
      specular_output_(device, s.chains * pixels() * sizeof(glm::vec4), kStorage, "specular output"),
      specular_accumulation_(device, s.chains * pixels() * sizeof(glm::vec4), kStorage, "specular accumulation"),
      history_(device, (s.temporal_history_pre_spatial ? s.chains * pixels() : 1) * sizeof(GiReservoir), kStorage,
               "GI history reservoirs"),
      initial_temporal_(device, compiler, s),
      spatial_shade_(device, compiler, s),
      stats_host_(device, stats_),
      counters_(device, s.path_counters ? sizeof(GiCounters) : sizeof(std::uint32_t), kStorage, "GI path counters") {
  if (s.specular) specular_.emplace(device, compiler, s);
  counters_.fill_zero();
  if (s.path_counters) counters_host_.emplace(device, counters_);
  for (Buffer* b : {&stored_, &mid_, &surfaces_, &output_, &accumulation_, &stats_, &specular_output_,
                    &specular_accumulation_, &history_})
    b->fill_zero();
}

void GiPipeline::bind(const SceneResources& scene, const Buffer& gbuffer, const WorldCache* world_cache) {
  GiBuffers b{&gbuffer, &stored_, &mid_, &surfaces_, &output_, &accumulation_, &stats_, &specular_output_,
              &specular_accumulation_, &history_};
  if (settings_.path_counters) b.counters = &counters_;
  if (settings_.queries_world_cache()) {
    if (!world_cache) throw std::logic_error("GiPipeline::bind: hit_radiance world_cache without a world cache");
    b.world_cache = world_cache->buffer_table();
  }
  initial_temporal_.bind(scene, b);
  spatial_shade_.bind(scene, b);
  if (specular_) specular_->bind(scene, b);
}

void GiPipeline::record(VkCommandBuffer cmd, GpuTimer& timer, bool accumulate, std::uint32_t frame_index,
                        std::uint32_t seed) {
  // Zeroed on the queue, before this frame's passes count into it.
  stats_.record_fill_zero(cmd);
  if (settings_.path_counters) counters_.record_fill_zero(cmd);
  GiPushConstants push{};
  push.chain_count = settings_.chains;
  push.history_valid = history_valid_ ? 1u : 0u;
  push.accumulate = accumulate ? 1u : 0u;
  push.permutation = pcg_hash(frame_index ^ pcg_hash(seed ^ RNG_DOMAIN_GI_PERMUTATION));
  timer.begin(cmd, "gi_initial_temporal");
  initial_temporal_.record(cmd, width_, height_, push);
  timer.end(cmd);
  compute_barrier(cmd);
  timer.begin(cmd, "gi_spatial_shade");
  spatial_shade_.record(cmd, width_, height_, push);
  timer.end(cmd);
  compute_barrier(cmd);
  if (specular_) {
    timer.begin(cmd, "specular_gi");
    specular_->record(cmd, width_, height_, push);
    timer.end(cmd);
    compute_barrier(cmd);
  }
  history_valid_ = true;
}

void GiPipeline::reset_accumulation() {
  accumulation_.fill_zero();
  specular_accumulation_.fill_zero();
}

Image GiPipeline::channel(const Buffer& buffer, std::uint32_t chain, bool mean) const {
  if (chain >= settings_.chains) throw std::out_of_range("GiPipeline: chain " + std::to_string(chain));
  const auto texels = buffer.download<glm::vec4>(pixels(), chain * pixels());  // the chain's slice only
  Image img(width_, height_);
  for (std::size_t i = 0; i < pixels(); ++i) {
    const glm::vec4 s = texels[i];
    img.pixels[i] = !mean ? glm::vec3(s) : (s.w > 0.0f ? glm::vec3(s) / s.w : glm::vec3(0.0f));
  }
  return img;
}

Image GiPipeline::gi_frame(std::uint32_t chain) const { return channel(output_, chain, false); }
Image GiPipeline::gi_mean(std::uint32_t chain) const { return channel(accumulation_, chain, true); }
Image GiPipeline::specular_frame(std::uint32_t chain) const { return channel(specular_output_, chain, false); }
Image GiPipeline::specular_mean(std::uint32_t chain) const { return channel(specular_accumulation_, chain, true); }

GiFrameStats GiPipeline::stats() const {
  const GiStats s = stats_host_.read<GiStats>(1)[0];
  GiFrameStats f;
  f.merges = s.merges;
  f.rejections = s.rejections;
  std::memcpy(&f.max_accepted_j, &s.max_accepted_j_bits, sizeof(float));
  f.nonfinite_jacobians = s.nonfinite_jacobians;
  f.nonfinite_reservoirs = s.nonfinite_reservoirs;
  f.nonfinite_output = s.nonfinite_output;
  f.temporal_edge_pixels = s.temporal_edge_pixels;
  f.temporal_edge_reused = s.temporal_edge_reused;
  f.log2_j_histogram.assign(std::begin(s.histogram), std::end(s.histogram));
  if (counters_host_) f.counters = counters_host_->read<GiCounters>(1)[0];
  return f;
}

void GiPipeline::list_state(StateList& out) {
  const std::uint64_t c = settings_.chains, h = height_, w = width_;
  out.push_back({"gi/stored_reservoirs", &stored_, "<f4", {c, h, w, 12}, "GiReservoir (core/shared/restir_gi.h)"});
  out.push_back({"gi/mid_reservoirs", &mid_, "<f4", {c, h, w, 12}, "GiReservoir (core/shared/restir_gi.h)"});
  if (settings_.temporal_history_pre_spatial)
    out.push_back({"gi/history_reservoirs", &history_, "<f4", {c, h, w, 12}, "GiReservoir (core/shared/restir_gi.h)"});
  out.push_back({"gi/surfaces", &surfaces_, "<f4", {h, w, 12}, "GiSurface (gpu/shaders/gi_bindings.h)"});
  out.push_back({"gi/output", &output_, "<f4", {c, h, w, 4}, "rgb diffuse GI, w 1 on a hit"});
  out.push_back({"gi/accumulation", &accumulation_, "<f4", {c, h, w, 4}, "rgb sum, w frames"});
  out.push_back({"gi/stats", &stats_, "<u4", {40}, "GiStats (core/shared/restir_gi.h)"});
  if (settings_.path_counters)
    out.push_back({"gi/counters", &counters_, "<u4", {4}, "GiCounters (core/shared/restir_gi.h)"});
  if (specular_) {
    out.push_back({"specular/output", &specular_output_, "<f4", {c, h, w, 4}, "rgb specular GI, w 1 on a hit"});
    out.push_back({"specular/accumulation", &specular_accumulation_, "<f4", {c, h, w, 4}, "rgb sum, w frames"});
  }
}

void GiPipeline::save_host_state(HostState& out) const {
  out.push_back({"gi/flags", {history_valid_ ? 1u : 0u}});
}

void GiPipeline::restore_host_state(const HostState& in) {
  const HostStateEntry* flags = find_host_state(in, "gi/flags");
  if (!flags || flags->words.size() != 1)
    throw std::invalid_argument("GiPipeline::restore_host_state: gi/flags (1 word) needed");
  history_valid_ = flags->words[0] != 0;
}

}  // namespace gi::gpu
