#include "gpu/passes/world_cache.h"

#include <algorithm>
#include <bit>
#include <cstddef>

#include <fmt/format.h>

#include "core/errors.h"
#include "gpu/device.h"
#include "gpu/profile_keys.h"
#include "gpu/realtime_settings.h"
#include "gpu/shaders/bindings.h"
#include "gpu/shaders/di_bindings.h"
#include "gpu/shaders/world_cache_bindings.h"

namespace gi::gpu {

using namespace gi::shader;

static_assert(sizeof(WorldCacheGeometry) == 32);
static_assert(sizeof(WorldCachePending) == 36, "scalars only: std430 stride 36");
static_assert(sizeof(WorldCacheCounters) == 48);
static_assert(sizeof(WorldCacheStats) == 48);
static_assert(sizeof(WorldCachePush) == 16);

namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

// Every cache pass declares the same table (the scene's bindings, the
// G-buffer, the cache's 50-64), so one list serves them all.
std::vector<DescriptorBinding> cache_bindings() {
  std::vector<DescriptorBinding> b = scene_descriptor_bindings();
  b.push_back({BINDING_GBUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  for (std::uint32_t i = BINDING_WC_CHECKSUMS; i <= BINDING_WC_VIEW; ++i)
    b.push_back({i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  b.push_back({BINDING_LIGHT_TILE_PACKED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});  // direct-light candidates
  return b;
}

ComputePass make_pass(Device& device, ShaderCompiler& compiler, const char* name,
                      const std::vector<ShaderDefine>& defines) {
  const std::string file = fmt::format("gpu/shaders/{}.comp", name);
  return ComputePass(device, name, compiler.compile_file(file, defines).spirv, cache_bindings(),
                     sizeof(WorldCachePush));
}

// Shader writes → reads, writes and indirect-argument reads of later passes.
void indirect_barrier(VkCommandBuffer cmd) {
  VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                    VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                           VK_PIPELINE_STAGE_HOST_BIT,
                       0, 1, &b, 0, nullptr, 0, nullptr);
}

// The profile key behind a field (gpu/profile_keys.h): the errors name it.
template <class T>
const std::string& key_of(T WorldCacheSettings::*member) {
  return profile_key_of(&RealtimeSettings::cache, member);
}

WorldCacheSettings checked(const Device& device, const WorldCacheSettings& s) {
  if (!std::has_single_bit(s.cells) || s.cells < WORLD_CACHE_SCAN_BLOCK)
    throw InputError(key_of(&WorldCacheSettings::cells), "",
                     fmt::format("a power of two of at least {}, got {}", WORLD_CACHE_SCAN_BLOCK, s.cells));
  if (s.lifetime == 0) throw InputError(key_of(&WorldCacheSettings::lifetime), "", "a lifetime of at least 1 frame");
  const std::uint32_t widest =
      std::min(device.limits().maxComputeWorkGroupSize[0], device.limits().maxComputeWorkGroupInvocations);
  if (s.update_workgroup_size == 0 || s.update_workgroup_size > widest)
    throw InputError(key_of(&WorldCacheSettings::update_workgroup_size), "",
                     fmt::format("a workgroup width from 1 to {} (this device's limit), got {}", widest,
                                 s.update_workgroup_size));
  return s;
}

}  // namespace

std::vector<ShaderDefine> WorldCacheSettings::defines(std::uint32_t pending_capacity) const {
  // Floats printed to round-trip, as GLSL float literals.
  auto f = [](float v) {
    std::string t = fmt::format("{:.9g}", v);
    return t.find_first_of(".e") == std::string::npos ? t + ".0" : t;
  };
  auto u = [](std::uint32_t v) { return std::to_string(v) + "u"; };
  std::vector<ShaderDefine> d = {{"WORLD_CACHE_CELLS", u(cells)},
                                 {"WORLD_CACHE_LIFETIME", u(lifetime)},
                                 {"WORLD_CACHE_MAX_PROBE_STEPS", u(max_probe_steps)},
                                 {"WORLD_CACHE_LINEAR_PROBING", linear_probing ? "1" : "0"},
                                 {"WORLD_CACHE_CELL_SIZE_BASE", f(cell_size_base)},
                                 {"WORLD_CACHE_LOD_SCALE", f(lod_scale)},
                                 {"WORLD_CACHE_STOCHASTIC_LOD", stochastic_lod ? "1" : "0"},
                                 {"WORLD_CACHE_JITTER", jitter ? "1" : "0"},
                                 {"WORLD_CACHE_JITTER_LOD_REDRAWN", jitter_lod_redrawn ? "1" : "0"},
                                 {"WORLD_CACHE_NORMAL_KEY_SCALE", f(normal_key_scale)},
                                 {"WORLD_CACHE_LEAK_RULE", first_bounce_leak_rule ? "1" : "0"},
                                 {"WORLD_CACHE_UPDATE_SOFT_CAP", std::to_string(update_soft_cap)},
                                 {"WORLD_CACHE_UPDATE_GROUP", u(update_workgroup_size)},
                                 {"WORLD_CACHE_C2C_FULL", cache_to_cache_full ? "1" : "0"},
                                 {"WORLD_CACHE_ADAPTIVE", adaptive_blend ? "1" : "0"},
                                 {"WORLD_CACHE_MAX_SAMPLES", f(max_samples)},
                                 {"WORLD_CACHE_ADAPTIVE_EXPONENT", f(adaptive_exponent)},
                                 {"WORLD_CACHE_DELTA_BLEND", f(delta_blend)},
                                 {"WORLD_CACHE_DI_SAMPLES", u(di_samples)},
                                 {"WORLD_CACHE_GI_TMAX", f(gi_ray_tmax)},
                                 {"WORLD_CACHE_LIGHT_EXPOSURE", f(light_exposure)},
                                 {"WORLD_CACHE_LOG2_RADIANCE", log2_radiance ? "1" : "0"},
                                 {"WORLD_CACHE_SECONDARY_HITS_FULL", secondary_hits_full ? "1" : "0"},
                                 {"WORLD_CACHE_SECONDARY_ALBEDO_BASE", secondary_albedo_base ? "1" : "0"},
                                 {"WORLD_CACHE_HIT_NORMAL_VERTEX", hit_normal_vertex ? "1" : "0"},
                                 {"WORLD_CACHE_DROP_ZERO_CHANNEL", drop_zero_channel_light ? "1" : "0"},
                                 {"WORLD_CACHE_DI_COSINE_MISSING", direct_light_cosine_missing ? "1" : "0"},
                                 {"WORLD_CACHE_TILE_CANDIDATES", tile_candidates ? "1" : "0"},
                                 {"WORLD_CACHE_TILE_COUNT", u(tile_count)},
                                 {"WORLD_CACHE_TILE_SAMPLES", u(tile_samples)},
                                 {"WORLD_CACHE_GLOSSY_ROUGHNESS", f(glossy_roughness)},
                                 {"WORLD_CACHE_GLOSSY_BOUNCES", u(glossy_bounces)},
                                 {"WORLD_CACHE_PENDING_CAPACITY", u(pending_capacity)}};
  if (root_frame) d.push_back({"WORLD_CACHE_ROOT_FRAME", ""});
  if (sun_center) d.push_back({"LIGHT_SUN_CENTER", "1"});
  // Only where set: the variants that normalise keep their compiled shaders.
  if (gi_reach_cosine) d.push_back({"WORLD_CACHE_GI_REACH_COSINE", "1"});
  return d;
}

WorldCache::WorldCache(Device& device, ShaderCompiler& compiler, const WorldCacheSettings& settings,
                       std::uint32_t width, std::uint32_t height)
    : settings_(checked(device, settings)),
      width_(width),
      height_(height),
      // One record per query at most: a query pass has pixels or active cells of them.
      pending_capacity_(std::max(width * height * (1u + settings.external_queries_per_pixel), settings.cells)),
      checksums_(device, settings.cells * sizeof(std::uint32_t), kStorage, "world cache checksums"),
      life_(device, settings.cells * sizeof(std::uint32_t), kStorage, "world cache life"),
      radiance_(device, settings.cells * sizeof(glm::vec4), kStorage, "world cache radiance"),
      delta_(device, settings.cells * sizeof(float), kStorage, "world cache luminance delta"),
      geometry_(device, settings.cells * sizeof(WorldCacheGeometry), kStorage, "world cache geometry"),
      root_frame_(device, settings.cells * sizeof(std::uint32_t), kStorage, "world cache root frame"),
      claims_(device, settings.cells * sizeof(std::uint32_t), kStorage, "world cache claims"),
      active_(device, settings.cells * sizeof(std::uint32_t), kStorage, "world cache active cells"),
      active_state_(device, settings.cells * sizeof(glm::uvec2), kStorage, "world cache active state"),
      new_radiance_(device, settings.cells * sizeof(glm::vec4), kStorage, "world cache new radiance"),
      block_sums_(device, settings.cells / WORLD_CACHE_SCAN_BLOCK * sizeof(std::uint32_t), kStorage,
                  "world cache block sums"),
      counters_(device, sizeof(WorldCacheCounters), kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                "world cache counters"),
      pending_(device, std::size_t(pending_capacity_) * sizeof(WorldCachePending), kStorage,
               "world cache pending insertions"),
      stats_(device, sizeof(WorldCacheStats), kStorage, "world cache stats"),
      // One texel when the view is off: the binding must still hold a buffer.
      view_(device, (settings.view ? std::size_t(width) * height : 1u) * sizeof(glm::vec4), kStorage,
            "world cache view"),
      decay_(make_pass(device, compiler, "world_cache_decay", settings.defines(pending_capacity_))),
      compact_scan_(make_pass(device, compiler, "world_cache_compact_scan", settings.defines(pending_capacity_))),
      compact_write_(make_pass(device, compiler, "world_cache_compact_write", settings.defines(pending_capacity_))),
      sample_di_(make_pass(device, compiler, "world_cache_sample_di", settings.defines(pending_capacity_))),
      sample_gi_(make_pass(device, compiler, "world_cache_sample_gi", settings.defines(pending_capacity_))),
      pending_args_(make_pass(device, compiler, "world_cache_pending_args", settings.defines(pending_capacity_))),
      commit_(make_pass(device, compiler, "world_cache_commit", settings.defines(pending_capacity_))),
      blend_(make_pass(device, compiler, "world_cache_blend", settings.defines(pending_capacity_))),
      stats_pass_(make_pass(device, compiler, "world_cache_stats", settings.defines(pending_capacity_))),
      counters_host_(device, counters_),
      stats_host_(device, stats_) {
  if (settings.view)
    query_pixels_.emplace(make_pass(device, compiler, "world_cache_query_pixels", settings.defines(pending_capacity_)));
  for (Buffer* b : {&checksums_, &life_, &radiance_, &delta_, &geometry_, &root_frame_, &claims_, &active_,
                    &active_state_, &new_radiance_, &block_sums_, &counters_, &pending_, &stats_, &view_})
    b->fill_zero();
}

std::vector<std::pair<std::uint32_t, const Buffer*>> WorldCache::buffer_table() const {
  return {{BINDING_WC_CHECKSUMS, &checksums_},   {BINDING_WC_LIFE, &life_},
          {BINDING_WC_RADIANCE, &radiance_},     {BINDING_WC_DELTA, &delta_},
          {BINDING_WC_GEOMETRY, &geometry_},     {BINDING_WC_ROOT_FRAME, &root_frame_},
          {BINDING_WC_CLAIMS, &claims_},         {BINDING_WC_ACTIVE, &active_},
          {BINDING_WC_ACTIVE_STATE, &active_state_}, {BINDING_WC_NEW_RADIANCE, &new_radiance_},
          {BINDING_WC_BLOCK_SUMS, &block_sums_}, {BINDING_WC_COUNTERS, &counters_},
          {BINDING_WC_PENDING, &pending_},       {BINDING_WC_STATS, &stats_},
          {BINDING_WC_VIEW, &view_}};
}

void WorldCache::bind(const SceneResources& scene, const Buffer& gbuffer, const Buffer* light_tiles) {
  if (settings_.tile_candidates && !light_tiles)
    throw DeviceError("WorldCache: light-tile candidates without DI's light tiles");
  const std::pair<std::uint32_t, const Buffer*> table[] = {
      {BINDING_GBUFFER, &gbuffer},          {BINDING_WC_CHECKSUMS, &checksums_},
      {BINDING_WC_LIFE, &life_},            {BINDING_WC_RADIANCE, &radiance_},
      {BINDING_WC_DELTA, &delta_},          {BINDING_WC_GEOMETRY, &geometry_},
      {BINDING_WC_ROOT_FRAME, &root_frame_}, {BINDING_WC_CLAIMS, &claims_},
      {BINDING_WC_ACTIVE, &active_},        {BINDING_WC_ACTIVE_STATE, &active_state_},
      {BINDING_WC_NEW_RADIANCE, &new_radiance_}, {BINDING_WC_BLOCK_SUMS, &block_sums_},
      {BINDING_WC_COUNTERS, &counters_},    {BINDING_WC_PENDING, &pending_},
      {BINDING_WC_STATS, &stats_},          {BINDING_WC_VIEW, &view_},
      {BINDING_LIGHT_TILE_PACKED, light_tiles ? light_tiles : &view_}};  // any buffer when unread
  std::vector<ComputePass*> passes = {&decay_,      &compact_scan_, &compact_write_, &sample_di_, &sample_gi_,
                                      &pending_args_, &commit_,      &blend_,         &stats_pass_};
  if (query_pixels_) passes.push_back(&*query_pixels_);
  for (ComputePass* p : passes) {
    p->bind_scene(scene);
    for (const auto& [binding, buffer] : table) p->bind_buffer(binding, *buffer);
  }
}

namespace {
constexpr VkDeviceSize kActiveArgs = offsetof(WorldCacheCounters, active_args);
constexpr VkDeviceSize kGiPendingArgs = offsetof(WorldCacheCounters, gi_pending);
constexpr VkDeviceSize kPixelPendingArgs = offsetof(WorldCacheCounters, pixel_pending);
constexpr WorldCachePush kCacheToCache{0, 0, 0, 0}, kPixelRooted{1, 0, 0, 0};
}  // namespace

void WorldCache::record(VkCommandBuffer cmd, GpuTimer& timer) {
  record_update(cmd, timer);
  timer.begin(cmd, "world_cache_commit");
  commit_pixel_queries(cmd);
  timer.end(cmd);
  indirect_barrier(cmd);
  record_stats(cmd, timer);
}

void WorldCache::record_commit(VkCommandBuffer cmd, GpuTimer& timer) {
  timer.begin(cmd, "world_cache_commit");
  commit_pixel_queries(cmd);
  timer.end(cmd);
  indirect_barrier(cmd);
  record_stats(cmd, timer);
}

// decay .. blend, then (settings.view) the cache view's pixel-rooted queries.
// A sweep's workgroup walks one compaction block (world_cache_sweep.glsl).
static_assert(WORLD_CACHE_CELL_GROUP * WORLD_CACHE_SWEEP_CELLS == WORLD_CACHE_SCAN_BLOCK);
static_assert(WORLD_CACHE_SWEEP_CELLS % 4u == 0u);

void WorldCache::record_update(VkCommandBuffer cmd, GpuTimer& timer) {
  const std::uint32_t cells = settings_.cells;
  const std::uint32_t blocks = cells / WORLD_CACHE_SCAN_BLOCK;

  timer.begin(cmd, "world_cache_decay");
  decay_.dispatch(cmd, blocks, 1);
  timer.end(cmd);
  indirect_barrier(cmd);

  timer.begin(cmd, "world_cache_compact");  // the blocks' live counts came with the decay
  compact_scan_.dispatch(cmd, 1, 1);
  indirect_barrier(cmd);
  compact_write_.dispatch(cmd, blocks, 1);
  timer.end(cmd);
  indirect_barrier(cmd);

  timer.begin(cmd, "world_cache_sample_di");
  sample_di_.dispatch_indirect(cmd, counters_, kActiveArgs);
  timer.end(cmd);
  indirect_barrier(cmd);

  timer.begin(cmd, "world_cache_sample_gi");
  sample_gi_.dispatch_indirect(cmd, counters_, kActiveArgs);
  indirect_barrier(cmd);
  pending_args_.dispatch(cmd, 1, 1, 1, &kCacheToCache);
  indirect_barrier(cmd);
  commit_.dispatch_indirect(cmd, counters_, kGiPendingArgs, &kCacheToCache);
  timer.end(cmd);
  indirect_barrier(cmd);

  timer.begin(cmd, "world_cache_blend");
  blend_.dispatch_indirect(cmd, counters_, kActiveArgs);
  timer.end(cmd);
  indirect_barrier(cmd);

  if (!query_pixels_) return;
  timer.begin(cmd, "world_cache_view");
  query_pixels_->dispatch(cmd, group_count(width_, RAY_WORKGROUP_X), group_count(height_, RAY_WORKGROUP_Y));
  timer.end(cmd);
  indirect_barrier(cmd);
}

// The pixel-rooted list's commit: the lowest query id's record per claimed slot.
void WorldCache::commit_pixel_queries(VkCommandBuffer cmd) {
  pending_args_.dispatch(cmd, 1, 1, 1, &kPixelRooted);
  indirect_barrier(cmd);
  commit_.dispatch_indirect(cmd, counters_, kPixelPendingArgs, &kPixelRooted);
}

void WorldCache::record_stats(VkCommandBuffer cmd, GpuTimer& timer) {
  if (!settings_.stats) return;
  timer.begin(cmd, "world_cache_stats");
  stats_pass_.dispatch(cmd, settings_.cells / WORLD_CACHE_SCAN_BLOCK, 1);
  timer.end(cmd);
  indirect_barrier(cmd);
}

void WorldCache::record_readbacks(VkCommandBuffer cmd) const {
  counters_host_.record_copy(cmd);
  stats_host_.record_copy(cmd);
}

WorldCacheFrameStats WorldCache::stats() const {
  if (!settings_.stats) throw DeviceError("WorldCache::stats: the statistics pass is off (WorldCacheSettings::stats)");
  const WorldCacheCounters c = counters_host_.read<WorldCacheCounters>(1)[0];
  const WorldCacheStats s = stats_host_.read<WorldCacheStats>(1)[0];
  WorldCacheFrameStats f;
  f.active_cells = c.active_args.w;
  f.live_cells = s.live_cells;
  f.sampled_cells = s.sampled_cells;
  const double sum = (double(s.radiance_sum_hi) * 4294967296.0 + double(s.radiance_sum_lo)) / WORLD_CACHE_STATS_SCALE;
  f.mean_radiance = s.sampled_cells ? sum / s.sampled_cells : 0.0;
  f.over_age_cells = s.over_age_cells;
  f.oldest_age = s.oldest_age;
  f.life_out_of_range = s.life_out_of_range;
  f.dead_not_empty = s.dead_not_empty;
  f.nonfinite_cells = s.nonfinite_cells;
  f.updated_cells = s.updated_cells;
  return f;
}

Image WorldCache::view() const {
  if (!settings_.view) throw DeviceError("WorldCache::view: the cache view is off (WorldCacheSettings::view)");
  const auto v = view_.download<glm::vec4>(std::size_t(width_) * height_);
  Image img(width_, height_);
  for (std::size_t i = 0; i < v.size(); ++i) img.pixels[i] = glm::vec3(v[i]);
  return img;
}

void WorldCache::list_state(StateList& out) {
  const std::uint64_t n = settings_.cells;
  out.push_back({"world_cache/checksums", &checksums_, "<u4", {n}});
  out.push_back({"world_cache/life", &life_, "<u4", {n}});
  out.push_back({"world_cache/radiance", &radiance_, "<f4", {n, 4}, "rgb irradiance, a sample count"});
  out.push_back({"world_cache/luminance_delta", &delta_, "<f4", {n}});
  out.push_back({"world_cache/geometry", &geometry_, "<f4", {n, 8}, "WorldCacheGeometry (core/shared/world_cache.h)"});
  out.push_back({"world_cache/root_frame", &root_frame_, "<u4", {n}});
}

}  // namespace gi::gpu
