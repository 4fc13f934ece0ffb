#include "gpu/renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/errors.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/bindings.h"

namespace gi::gpu {

namespace {

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

Buffer make_geometry_buffer(Device& device, const void* data, std::size_t bytes, const char* name) {
  // Only the rayquery backend builds from these buffers (device addresses and
  // build-input usage need extensions the bvh backend must not require).
  const VkBufferUsageFlags usage = device.backend() == TraceBackend::rayquery
                                       ? AccelerationStructures::geometry_buffer_usage()
                                       : VkBufferUsageFlags(VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  Buffer b(device, bytes, usage, name);
  b.upload_bytes(data, bytes);
  return b;
}

}  // namespace

Renderer::Renderer(Device& device, ShaderCompiler& compiler, const FlatGeometry& geometry,
                   const RendererOptions& options)
    : device_(device),
      options_(options),
      vertices_(make_geometry_buffer(device, geometry.vertices.data(), geometry.vertices.size() * sizeof(GpuVertex),
                                     "vertices")),
      indices_(make_geometry_buffer(device, geometry.indices.data(),
                                    geometry.indices.size() * sizeof(std::uint32_t), "indices")),
      frame_(device, sizeof(FrameConstants), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, "frame constants", BufferMemory::host_write),
      dfg_lut_(make_dfg_lut_buffer(device)),
      textures_(device),
      compiler_(compiler),
      timer_(device) {
  if (options.width == 0 || options.height == 0)
    throw DeviceError(fmt::format("Renderer: resolution {}x{} is empty", options.width, options.height));
  // The tracing backend: its acceleration structure, and its shader variant
  // for every pass compiled from here on (passes never know which runs).
  std::vector<ShaderDefine> defines = trace_backend_defines(device);
  defines.push_back({"NORMAL_MAP_DECODE", std::to_string(options.normal_map_decode)});
  compiler.set_global_defines(std::move(defines));
  if (device.backend() == TraceBackend::bvh) bvh_.emplace(device, geometry);
  else as_.emplace(device, geometry, vertices_, indices_);
  if (options.di && options.di->traces_previous_scene()) {  // DI's temporal MIS visibility (Bevy #25046)
    if (as_) as_->keep_previous_tlas();
    if (bvh_) bvh_->keep_previous_nodes();
  }
  mesh_ranges_ = geometry.meshes;
  triangle_count_ = geometry.indices.size() / 3;
  textures_.update_geometry(geometry);
  const std::size_t pixels = pixel_count();
  if (options_.timing_calibration) {
    calibration_.emplace(device, compiler);
    calibration_ms_ = std::nan("");
  }
  if (options_.gbuffer) {
    visibility_ = Buffer(device, pixels * sizeof(glm::uvec2), kStorage, "visibility");
    depth_ = Buffer(device, pixels * sizeof(float), kStorage, "depth");
    gbuffer_ = Buffer(device, pixels * sizeof(GBufferTexel), kStorage, "gbuffer");
    primary_visibility_.emplace(device, compiler);
    // Default ID space: each mesh's LOD-0 meshlets (set_cluster_ids replaces it).
    for (std::uint32_t m = 0; m < geometry.meshes.size(); ++m)
      mesh_clusters_.push_back(lod0_cluster_ids(geometry, m, 1u << cluster_layout_.triangle_bits));
    gbuffer_resolve_.emplace(device, compiler, options_.motion_vectors);
  }
  if (options_.reference) {
    reference_a_ = Buffer(device, pixels * sizeof(glm::vec4), kStorage, "reference A");
    reference_b_ = Buffer(device, pixels * sizeof(glm::vec4), kStorage, "reference B");
    nonfinite_ = Buffer(device, sizeof(std::uint32_t), kStorage, "reference non-finite count");
    nonfinite_host_.emplace(device, nonfinite_);
    reset_accumulation();
    reference_path_trace_.emplace(device, compiler, options_.reference_options);
  }
  if (options_.di) {
    if (!options_.gbuffer) throw DeviceError("Renderer: realtime DI needs the G-buffer (RendererOptions::gbuffer)");
    di_.emplace(device, compiler, *options_.di, options.width, options.height);
  }
  // ReSTIR GI and specular GI querying the cache (restir_gi.hit_radiance
  // world_cache): their queries join the pixel-rooted pending list.
  const bool gi_queries_cache = options_.gi && options_.gi->queries_world_cache();
  if (gi_queries_cache && !options_.world_cache)
    throw DeviceError("Renderer: restir_gi.hit_radiance world_cache needs the world cache (RendererOptions::world_cache)");
  if (options_.world_cache) {
    if (!options_.gbuffer) throw DeviceError("Renderer: the world cache needs the G-buffer (RendererOptions::gbuffer)");
    WorldCacheSettings cache = *options_.world_cache;
    // GI's initial samples (one id block each: the first, specular GI's, then
    // the extra candidates of restir_gi.initial_samples, gi_cache_query_id).
    if (gi_queries_cache) {
      const std::uint32_t extra = options_.gi->initial_samples - 1u;
      cache.external_queries_per_pixel =
          options_.gi->chains * (extra > 0 ? 2u + extra : (options_.gi->specular ? 2u : 1u));
    }
    if (cache.tile_candidates) {
      if (!di_) throw DeviceError("Renderer: the world cache's light-tile candidates need realtime DI's light tiles");
      cache.tile_count = options_.di->tile_count;  // the tiles as DI sized them
      cache.tile_samples = options_.di->samples_per_tile;
    }
    world_cache_.emplace(device, compiler, cache, options.width, options.height);
  }
  if (options_.gi) {
    if (!options_.di) throw DeviceError("Renderer: GI needs realtime DI (RendererOptions::di)");
    GiSettings gi = *options_.gi;
    if (gi_queries_cache) gi.world_cache_defines = world_cache_->shader_defines();
    gi_.emplace(device, compiler, gi, options.width, options.height);
  }
  if (options_.frame_output) {
    if (!di_ && !options_.reference) throw DeviceError("Renderer: the frame output needs realtime DI or the reference");
    const FrameOutput::Mode mode = !di_ ? FrameOutput::Mode::reference
                                   : gi_ ? FrameOutput::Mode::di_gi
                                         : FrameOutput::Mode::di;
    frame_output_.emplace(device, compiler, options.width, options.height, mode);
  }
}

Renderer::~Renderer() { vkDeviceWaitIdle(device_.handle()); }

void Renderer::ensure_buffer(Buffer& buffer, VkDeviceSize bytes, VkBufferUsageFlags usage, const char* name) {
  if (buffer && buffer.size() >= bytes) return;
  buffer = Buffer(device_, std::max<VkDeviceSize>(bytes, 16), usage, name);
  bindings_dirty_ = true;
}

void Renderer::update_geometry(const FlatGeometry& geometry) {
  const std::size_t old_meshes = mesh_ranges_.size();
  if (geometry.meshes.size() < old_meshes ||
      !std::equal(mesh_ranges_.begin(), mesh_ranges_.end(), geometry.meshes.begin()))
    throw DeviceError("Renderer::update_geometry: a mesh changed or went away; meshes may only be appended");
  if (geometry.meshes.size() == old_meshes) return;  // a spawn of an existing mesh: instances only
  vertices_ = make_geometry_buffer(device_, geometry.vertices.data(), geometry.vertices.size() * sizeof(GpuVertex),
                                   "vertices");
  indices_ = make_geometry_buffer(device_, geometry.indices.data(), geometry.indices.size() * sizeof(std::uint32_t),
                                  "indices");
  bindings_dirty_ = true;
  textures_.update_geometry(geometry);
  if (as_) as_->add_meshes(geometry, vertices_, indices_);
  if (bvh_) bvh_->add_meshes(geometry);
  mesh_ranges_ = geometry.meshes;
  triangle_count_ = geometry.indices.size() / 3;
  if (options_.gbuffer)
    for (std::uint32_t m = std::uint32_t(old_meshes); m < geometry.meshes.size(); ++m)
      mesh_clusters_.push_back(lod0_cluster_ids(geometry, m, 1u << cluster_layout_.triangle_bits));
}

void Renderer::update_scene(const FlatInstances& scene, const std::vector<bool>& visible) {
  ensure_buffer(instances_, scene.instances.size() * sizeof(GpuInstance), kStorage, "instances");
  ensure_buffer(materials_, scene.materials.size() * sizeof(GpuMaterial), kStorage, "materials");
  ensure_buffer(lights_, scene.lights.size() * sizeof(GpuLight), kStorage, "lights");
  instances_.upload(scene.instances);
  materials_.upload(scene.materials);
  lights_.upload(scene.lights);
  if (textures_.update_materials(scene)) bindings_dirty_ = true;
  if (as_) as_->update(scene.instances, visible);
  if (bvh_) bvh_->update(scene.instances, visible);
  if (options_.gbuffer) {  // instance ID ranges follow the visible set
    cluster_table_ = build_cluster_table(mesh_ranges_, triangle_count_, mesh_clusters_, scene.instances, visible,
                                         cluster_layout_);
    ensure_buffer(cluster_table_buffer_, cluster_table_.size() * sizeof(std::uint32_t), kStorage, "cluster table");
    cluster_table_buffer_.upload(cluster_table_);
  }
  if (di_) di_->update_lights(scene);
  update_previous_transforms(scene);
  if (as_ && as_->take_tlas_handle_changed()) bindings_dirty_ = true;
  if (bvh_ && bvh_->take_buffers_changed()) bindings_dirty_ = true;
  scene_uploaded_ = true;
}

void Renderer::update_previous_transforms(const FlatInstances& scene) {
  if (!options_.gbuffer) return;
  std::vector<glm::mat4> previous = scene.previous_object_to_world;
  if (previous.size() != scene.instances.size()) {
    previous.clear();
    for (const GpuInstance& inst : scene.instances) previous.push_back(inst.object_to_world);
  }
  ensure_buffer(previous_transforms_, previous.size() * sizeof(glm::mat4), kStorage, "previous transforms");
  if (!previous.empty()) previous_transforms_.upload(previous);
}

void Renderer::bind_passes() {
  SceneResources scene{as_ ? as_->tlas() : VK_NULL_HANDLE, &vertices_, &indices_, &instances_, &materials_,
                       &lights_, &frame_};
  scene.dfg_lut = &dfg_lut_;
  textures_.add_to(scene);
  if (bvh_) {
    scene.bvh_nodes = &bvh_->nodes();
    scene.bvh_triangles = &bvh_->triangles();
    scene.previous_bvh_nodes = &bvh_->previous_nodes();
  }
  if (as_) scene.previous_tlas = as_->previous_tlas();
  if (primary_visibility_) primary_visibility_->bind(scene, visibility_, depth_, cluster_table_buffer_);
  if (gbuffer_resolve_) gbuffer_resolve_->bind(scene, visibility_, depth_, gbuffer_, cluster_table_buffer_, previous_transforms_);
  if (reference_path_trace_) reference_path_trace_->bind(scene, reference_a_, reference_b_, nonfinite_);
  if (di_) di_->bind(scene, gbuffer_);
  if (world_cache_) world_cache_->bind(scene, gbuffer_, di_ ? &di_->tile_packed() : nullptr);
  if (gi_) gi_->bind(scene, gbuffer_, world_cache_ ? &*world_cache_ : nullptr);
  if (frame_output_) {
    if (di_) frame_output_->bind(di_->output_buffer(), gi_ ? &gi_->output_buffer() : nullptr,
                                 gi_ ? &gi_->specular_output_buffer() : nullptr);
    else frame_output_->bind(reference_a_, &reference_b_, nullptr);
  }
  bindings_dirty_ = false;
}

void Renderer::render_frame(const FrameConstants& frame) {
  submit_frame(frame);
  finish_frame();
}

void Renderer::submit_frame(const FrameConstants& frame) {
  if (!scene_uploaded_) throw DeviceError("Renderer::render_frame before update_scene");
  if (frame.resolution_frame.x != options_.width || frame.resolution_frame.y != options_.height)
    throw DeviceError(fmt::format("Renderer::render_frame: frame constants say {}x{}, the renderer is {}x{}",
                                  frame.resolution_frame.x, frame.resolution_frame.y, options_.width,
                                  options_.height));
  frame_.upload_bytes(&frame, sizeof frame);
  if (bindings_dirty_) bind_passes();
  const std::vector<HashRange> hash_ranges = std::exchange(next_frame_hashes_, {});
  if (!hash_ranges.empty()) {
    if (!state_hash_) state_hash_.emplace(device_, compiler_);
    state_hash_->ensure_slots(std::uint32_t(hash_ranges.size()));
  }
  const std::uint32_t w = options_.width, h = options_.height;
  submitted_hashes_ = hash_ranges.size();
  device_.submit([&](VkCommandBuffer cmd) {
    timer_.begin_frame(cmd);
    auto run = [&](const char* name, const auto& pass) {
      timer_.begin(cmd, name);
      pass.record(cmd, w, h);
      timer_.end(cmd);
      compute_barrier(cmd);
    };
    if (primary_visibility_) run("primary_visibility", *primary_visibility_);
    if (gbuffer_resolve_) run("gbuffer_resolve", *gbuffer_resolve_);
    if (reference_path_trace_) run("reference_path_trace", *reference_path_trace_);
    const bool cache_fed_by_gi = gi_ && gi_->settings().queries_world_cache();
    // Solari 0.17 updates the cache before it rebuilds the light tiles
    // (v0.17.0:realtime/node.rs:257,273): the update reads last frame's.
    const bool cache_before_tiles = cache_fed_by_gi && world_cache_->settings().tiles_previous_frame;
    if (cache_before_tiles) world_cache_->record_update(cmd, timer_);
    if (di_) di_->record(cmd, timer_, /*accumulate=*/true);
    if (cache_fed_by_gi) {
      // The cache's update and its view's queries, then GI and specular GI
      // querying it (this frame's blended radiance, pixel-rooted), then one
      // commit of every pixel-rooted insertion before next frame's decay.
      if (!cache_before_tiles) world_cache_->record_update(cmd, timer_);
      gi_->record(cmd, timer_, /*accumulate=*/true, frame.resolution_frame.z, frame.resolution_frame.w);
      world_cache_->record_commit(cmd, timer_);
    } else {
      if (world_cache_) world_cache_->record(cmd, timer_);
      if (gi_) gi_->record(cmd, timer_, /*accumulate=*/true, frame.resolution_frame.z, frame.resolution_frame.w);
    }
    if (frame_output_) frame_output_->record(cmd, timer_);
    // Last, not first: the frame's start overlaps the host's work on the
    // previous frame (its record and checks), which would time the host.
    if (calibration_) calibration_->record(cmd, timer_);
    // The small results read after every frame, copied for the host in this submission.
    if (world_cache_) world_cache_->record_readbacks(cmd);
    if (gi_) gi_->record_readbacks(cmd);
    if (nonfinite_host_) nonfinite_host_->record_copy(cmd);
    if (!hash_ranges.empty()) {
      timer_.begin(cmd, "state_hash");
      state_hash_->record_all(cmd, hash_ranges);
      timer_.end(cmd);
    }
  });
  frame_in_flight_ = true;
  nonfinite_reset_ = false;
}

void Renderer::finish_frame() {
  if (!frame_in_flight_) throw DeviceError("Renderer::finish_frame without submit_frame");
  device_.wait();
  frame_in_flight_ = false;
  // Next frame's "previous scene" is this frame's (kept only for DI's
  // temporal MIS visibility; a no-op otherwise).
  if (as_) as_->end_frame();
  if (bvh_) bvh_->end_frame();
  if (as_ && as_->take_tlas_handle_changed()) bindings_dirty_ = true;
  if (bvh_ && bvh_->take_buffers_changed()) bindings_dirty_ = true;
  timer_.resolve();
  pass_timings_.clear();
  for (const PassTiming& t : timer_.timings()) {
    if (calibration_ && t.name == TimingCalibration::kTimerName) calibration_ms_ = t.ms;
    else pass_timings_.push_back(t);
  }
  if (submitted_hashes_ > 0) frame_hashes_ = state_hash_->results(std::uint32_t(submitted_hashes_));
}

FrameOutput& Renderer::frame_output() {
  require(frame_output_.has_value(), "the frame output (RendererOptions::frame_output)");
  return *frame_output_;
}

const FrameOutput& Renderer::frame_output() const {
  require(frame_output_.has_value(), "the frame output (RendererOptions::frame_output)");
  return *frame_output_;
}

std::vector<std::string> Renderer::hash_buffers(const std::vector<HashRange>& ranges) {
  if (!state_hash_) state_hash_.emplace(device_, compiler_);
  return state_hash_->hash_now(ranges);
}

void Renderer::require(bool enabled, const char* what) const {
  if (!enabled) throw DeviceError(fmt::format("Renderer: {} is not enabled in RendererOptions", what));
}

const DiPipeline& Renderer::di() const {
  require(di_.has_value(), "realtime DI (RendererOptions::di)");
  return *di_;
}

const GiPipeline& Renderer::gi() const {
  require(gi_.has_value(), "ReSTIR GI (RendererOptions::gi)");
  return *gi_;
}

const WorldCache& Renderer::world_cache() const {
  require(world_cache_.has_value(), "the world cache (RendererOptions::world_cache)");
  return *world_cache_;
}

void Renderer::reset_accumulation() {
  if (di_) di_->reset_accumulation();
  if (gi_) gi_->reset_accumulation();
  if (!options_.reference) return;
  reference_a_.fill_zero();
  reference_b_.fill_zero();
  nonfinite_.fill_zero();
  nonfinite_reset_ = true;
}

Image Renderer::reference_mean() const {
  require(options_.reference, "the reference");
  const auto a = reference_a_.download<glm::vec4>(pixel_count());
  const auto b = reference_b_.download<glm::vec4>(pixel_count());
  Image img(options_.width, options_.height);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const float n = a[i].w + b[i].w;
    img.pixels[i] = n > 0.0f ? (glm::vec3(a[i]) + glm::vec3(b[i])) / n : glm::vec3(0.0f);
  }
  return img;
}

namespace {

Image add(Image a, const Image& b) {
  for (std::size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] += b.pixels[i];
  return a;
}

}  // namespace

Image Renderer::realtime_frame(std::uint32_t chain) const {
  Image img = di().frame(chain);
  if (has_gi()) img = add(add(std::move(img), gi().gi_frame(chain)), gi().specular_frame(chain));
  return img;
}

Image Renderer::realtime_mean(std::uint32_t chain) const {
  Image img = di().mean(chain);
  if (has_gi()) img = add(add(std::move(img), gi().gi_mean(chain)), gi().specular_mean(chain));
  return img;
}

Image Renderer::reference_half(int which) const {
  require(options_.reference, "the reference");
  if (which != 0 && which != 1) throw std::invalid_argument("reference_half: which must be 0 (A) or 1 (B)");
  const auto h = reference_sums(which);
  Image img(options_.width, options_.height);
  for (std::size_t i = 0; i < h.size(); ++i) img.pixels[i] = h[i].w > 0.0f ? glm::vec3(h[i]) / h[i].w : glm::vec3(0.0f);
  return img;
}

std::vector<glm::vec4> Renderer::reference_sums(int which) const {
  require(options_.reference, "the reference");
  if (which != 0 && which != 1) throw std::invalid_argument("reference_sums: which must be 0 (A) or 1 (B)");
  return (which == 0 ? reference_a_ : reference_b_).download<glm::vec4>(pixel_count());
}

std::uint64_t Renderer::reference_nonfinite_samples() const {
  require(options_.reference, "the reference");
  // The mirror the frame's submission filled; a reset since then zeroed the counter itself.
  return nonfinite_host_ && !nonfinite_reset_ ? nonfinite_host_->read<std::uint32_t>(1)[0]
                                              : nonfinite_.download<std::uint32_t>(1)[0];
}

const std::vector<std::string>& Renderer::gbuffer_layer_names() {
  static const std::vector<std::string> names = {"albedo",   "normal", "geometric_normal", "depth",
                                                 "motion",   "position", "emissive",       "material"};
  return names;
}

Image Renderer::gbuffer_layer(const std::string& name) const {
  require(options_.gbuffer, "the G-buffer");
  const auto texels = gbuffer_.download<GBufferTexel>(pixel_count());
  Image img(options_.width, options_.height);
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const GBufferTexel& t = texels[i];
    glm::vec3& o = img.pixels[i];
    if (name == "albedo") o = glm::vec3(t.base_color_metallic);
    else if (name == "normal") o = glm::vec3(t.shading_normal);
    else if (name == "geometric_normal") o = glm::vec3(t.geometric_normal);
    else if (name == "depth") o = glm::vec3(t.position_depth.w);
    else if (name == "motion") o = glm::vec3(t.motion_reflectance.x, t.motion_reflectance.y, t.motion_reflectance.z);
    else if (name == "position") o = glm::vec3(t.position_depth);
    else if (name == "emissive") o = glm::vec3(t.emissive_roughness);
    else if (name == "material")
      o = glm::vec3(t.base_color_metallic.w, t.emissive_roughness.w, t.motion_reflectance.w);
    else {
      std::string known;
      for (const auto& n : gbuffer_layer_names()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument(fmt::format("unknown G-buffer layer '{}' (known: {})", name, known));
    }
  }
  return img;
}

std::vector<glm::uvec2> Renderer::packed_visibility() const {
  require(options_.gbuffer, "primary visibility (RendererOptions::gbuffer)");
  return visibility_.download<glm::uvec2>(pixel_count());
}

std::vector<glm::uvec2> Renderer::visibility() const {
  std::vector<glm::uvec2> v = packed_visibility();
  for (glm::uvec2& p : v) {
    const DecodedVisibility d =
        p.x == shader::VISIBILITY_MISS ? DecodedVisibility{} : decode_packed_visibility(cluster_table_, p.x);
    p = d.valid ? glm::uvec2(d.instance, d.primitive) : glm::uvec2(shader::VISIBILITY_MISS);
  }
  return v;
}

void Renderer::set_cluster_ids(std::vector<MeshClusterIds> meshes, const ClusterIdLayout& layout) {
  require(options_.gbuffer, "primary visibility (RendererOptions::gbuffer)");
  if (meshes.size() != mesh_ranges_.size())
    throw DeviceError(fmt::format("Renderer::set_cluster_ids: {} meshes, the renderer has {}", meshes.size(),
                                  mesh_ranges_.size()));
  mesh_clusters_ = std::move(meshes);
  cluster_layout_ = layout;
}

void Renderer::list_state(StateList& out) {
  const std::uint64_t h = options_.height, w = options_.width;
  if (options_.gbuffer) {
    out.push_back({"gbuffer/visibility", &visibility_, "<u4", {h, w, 2}, "packed cluster id, instance channel"});
    out.push_back({"gbuffer/depth", &depth_, "<f4", {h, w}, "hit t, 0 = miss"});
    out.push_back({"gbuffer/texels", &gbuffer_, "<f4", {h, w, sizeof(GBufferTexel) / 4},
                   "GBufferTexel (gpu/shaders/gbuffer.h)"});
  }
  if (options_.reference) {
    out.push_back({"reference/half_a", &reference_a_, "<f4", {h, w, 4}, "rgb sum, w samples"});
    out.push_back({"reference/half_b", &reference_b_, "<f4", {h, w, 4}, "rgb sum, w samples"});
    out.push_back({"reference/nonfinite", &nonfinite_, "<u4", {1}, ""});
  }
  if (di_) di_->list_state(out);
  if (world_cache_) world_cache_->list_state(out);
  if (gi_) gi_->list_state(out);
}

void Renderer::save_host_state(HostState& out) const {
  if (di_) di_->save_host_state(out);
  if (gi_) gi_->save_host_state(out);
}

void Renderer::restore_host_state(const HostState& in) {
  if (di_) di_->restore_host_state(in);
  if (gi_) gi_->restore_host_state(in);
}

std::vector<float> Renderer::depth() const {
  require(options_.gbuffer, "primary visibility (RendererOptions::gbuffer)");
  return depth_.download<float>(pixel_count());
}

}  // namespace gi::gpu
