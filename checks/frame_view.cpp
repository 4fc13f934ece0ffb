// FrameView: every accessor first checks the check's declaration.
#include <stdexcept>

#include <fmt/format.h>

#include "gpu/renderer.h"
#include "checks/check.h"

namespace gi {

void FrameView::require(FrameInput input, const char* what) const {
  if (!allowed_.count(input))
    throw std::logic_error(fmt::format("a check read {} at frame {} without declaring it (CheckNeeds::reads)", what,
                                       data_.frame));
}

const Image& FrameView::output() const {
  require(FrameInput::output_image, "the output image");
  return data_.output ? *data_.output : data_.read_output();
}
double FrameView::output_luminance() const {
  require(FrameInput::output, "the output's luminance");
  return data_.output_luminance;
}
std::uint64_t FrameView::nonfinite_pixels() const {
  require(FrameInput::output, "the output's non-finite pixels");
  return data_.nonfinite_pixels;
}
const gpu::GiFrameStats* FrameView::gi_stats() const {
  require(FrameInput::gi_stats, "GI statistics");
  return data_.gi_stats;
}
double FrameView::gi_luminance() const {
  require(FrameInput::gi_luminance, "the GI luminance");
  return data_.gi_luminance;
}
const gpu::WorldCacheFrameStats* FrameView::cache_stats() const {
  require(FrameInput::cache_stats, "world cache statistics");
  return data_.cache_stats;
}
std::optional<double> FrameView::cache_view_luminance() const {
  require(FrameInput::cache_view, "the cache view");
  return data_.cache_view_luminance;
}
CacheCells FrameView::cache_cells() const {
  require(FrameInput::cache_cells, "the world cache's table");
  const gpu::WorldCache& cache = data_.renderer->world_cache();
  CacheCells c;
  c.checksums = cache.checksums();
  c.life = cache.life();
  for (const auto& g : cache.geometry()) {
    c.positions.push_back(g.position);
    c.normals.push_back(g.normal);
  }
  c.settings = &cache.settings();
  return c;
}
std::vector<std::array<std::uint32_t, 4>> FrameView::light_tile_samples(std::uint32_t& samples_per_tile) const {
  require(FrameInput::light_tiles, "the light tiles");
  const gpu::DiPipeline& di = data_.renderer->di();
  samples_per_tile = di.settings().samples_per_tile;
  std::vector<std::array<std::uint32_t, 4>> out;
  for (const auto& s : di.tile_samples(0)) out.push_back({s.light_id, s.triangle_id, s.seed, s.valid});
  return out;
}
std::vector<glm::uvec2> FrameView::packed_visibility() const {
  require(FrameInput::cluster_visibility, "packed visibility");
  return data_.renderer->packed_visibility();
}
const std::vector<std::uint32_t>& FrameView::cluster_table() const {
  require(FrameInput::cluster_visibility, "the cluster table");
  return data_.renderer->cluster_table();
}

bool FrameView::full_gi() const { return data_.renderer->has_gi(); }

std::uint32_t FrameView::chain_count() const {
  require(FrameInput::chains, "the chain count");
  return std::uint32_t(data_.chains.size());
}
const gpu::Renderer& FrameView::chain_pipeline(std::uint32_t chain) const {
  if (chain >= data_.chains.size())
    throw std::logic_error(fmt::format("a check read chain {} of a run with {} (CheckNeeds::chains)", chain,
                                       data_.chains.size()));
  return *data_.chains[chain];
}
Image FrameView::chain_frame(std::uint32_t chain) const {
  require(FrameInput::chains, "a chain's frame");
  return chain_pipeline(chain).realtime_frame(0);
}
Image FrameView::chain_mean(std::uint32_t chain) const {
  require(FrameInput::chains, "a chain's temporal mean");
  return chain_pipeline(chain).realtime_mean(0);
}
std::uint32_t FrameView::chain_window_frames() const {
  require(FrameInput::chains, "the chains' window");
  return data_.renderer->di().accumulated_frames(0);
}
Image FrameView::gbuffer_layer(const std::string& name) const {
  require(FrameInput::gbuffer_layers, "a G-buffer layer");
  return data_.renderer->gbuffer_layer(name);
}
Image FrameView::reference_half(int which) const {
  require(FrameInput::reference_halves, "a reference half");
  return data_.renderer->reference_half(which);
}
std::uint64_t FrameView::nonfinite_samples() const {
  require(FrameInput::nonfinite_samples, "non-finite samples");
  return data_.nonfinite_samples;
}

const Canvas& FrameView::rc_canvas() const {
  require(FrameInput::rc_canvas, "the canvas");
  return *data_.rc_canvas;
}

const RcSettings& FrameView::rc_settings() const {
  require(FrameInput::rc_canvas, "the cascades' settings");
  return *data_.rc_settings;
}

const RcReference& FrameView::rc_reference() const {
  require(FrameInput::rc_reference, "the 2D reference");
  return data_.rc_reference();
}

}  // namespace gi
