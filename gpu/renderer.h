// The facade the frame loop uses: owns the scene's GPU buffers, the
// acceleration structures, the enabled passes and their outputs. Only the
// passes the options enable are compiled (a scenario compiles only what it uses).
//
// Geometry events (spawn) call update_geometry, which builds the new meshes'
// acceleration structures and re-uploads the vertex and index buffers; every
// pass's state (reservoirs, world cache, last frame's surfaces, accumulation
// sums, host-side history) carries on, as in Bevy's Solari.
//
// Per frame: update_scene (uploads; TLAS rebuilt only when needed), then
// render_frame (records, submits and waits for the enabled passes, each
// bracketed by GPU timestamps), then read back what the checks need.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/clusters/cluster_table.h"
#include "core/image.h"
#include "core/scene_flatten.h"
#include "gpu/acceleration_structures.h"
#include "gpu/buffer.h"
#include "gpu/host_mirror.h"
#include "gpu/bvh_buffers.h"
#include "gpu/passes/buffer_hash.h"
#include "gpu/passes/di_pipeline.h"
#include "gpu/passes/frame_output.h"
#include "gpu/passes/gbuffer_resolve.h"
#include "gpu/passes/gi_pipeline.h"
#include "gpu/passes/primary_visibility.h"
#include "gpu/passes/reference_path_trace.h"
#include "gpu/passes/timing_calibration.h"
#include "gpu/scene_texture_buffers.h"
#include "gpu/passes/world_cache.h"
#include "gpu/state_buffers.h"
#include "gpu/timer.h"

namespace gi::gpu {

class Device;
class ShaderCompiler;

struct RendererOptions {
  std::uint32_t width = 0, height = 0;
  bool gbuffer = true;    // primary visibility + G-buffer resolve
  bool reference = true;  // GPU reference path tracer (accumulating)
  ReferencePathTraceOptions reference_options;  // its background (Scene::background)
  std::optional<DiSettings> di;  // realtime mode: light tiles + ReSTIR DI (needs gbuffer)
  std::optional<WorldCacheSettings> world_cache;  // the world cache and its cache view (needs gbuffer)
  std::optional<GiSettings> gi;  // ReSTIR GI + specular GI (needs di: the output is DI + GI + specular)
  // The output and the frame record's measures made on the GPU each frame
  // (gpu/passes/frame_output.h; needs di or reference): what the frame loop reads.
  bool frame_output = false;
  // The timing calibration kernel last in every frame (gpu/passes/timing_calibration.h):
  // the run sets it on a CPU device, where pass times need it to compare.
  bool timing_calibration = false;
  // How the realtime passes read normal maps (core/shared/texture_sampling.h
  // NORMAL_MAP_DECODE_*, the profile's textures.normal_map_decode); the
  // reference path tracer always decodes them as glTF says.
  std::uint32_t normal_map_decode = 2;
  // The G-buffer's motion vectors (the profile's temporal.motion_vectors).
  MotionVectors motion_vectors = MotionVectors::object;
};

class Renderer {
 public:
  Renderer(Device& device, ShaderCompiler& compiler, const FlatGeometry& geometry, const RendererOptions& options);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // The scene's meshes after a spawn: meshes appended since construction (or
  // the last call) get their BLASes and join the vertex and index buffers
  // (reallocated, re-uploaded); the earlier meshes must be unchanged (events
  // only append; DeviceError otherwise). Nothing else is touched: call
  // update_scene next for the instance list. New meshes own their LOD-0
  // meshlets' cluster IDs until set_cluster_ids names every mesh's.
  void update_geometry(const FlatGeometry& geometry);
  // Uploads instances, materials and lights; rebuilds the TLAS only when a
  // visible instance's transform or the visible set changed. visible[i] is
  // instance i's visibility (a missing entry = visible).
  void update_scene(const FlatInstances& instances, const std::vector<bool>& visible);
  // Uploads last frame's transforms alone (FlatInstances::previous_object_to_world,
  // this frame's where it is empty): what a frame whose only change is the
  // motion vectors' (ChangeSet::motion) needs. update_scene calls it.
  void update_previous_transforms(const FlatInstances& instances);
  // Records, submits and waits: visibility, G-buffer, reference (each only if
  // enabled), with timestamps. frame.resolution_frame.xy must match the options.
  void render_frame(const FrameConstants& frame);
  // The same in two halves: submit_frame records and submits without
  // waiting, so the host can work while the GPU renders; finish_frame waits
  // and reads the timestamps and the frame's hashes. Nothing may touch the
  // renderer's buffers between the two (a buffer transfer would wait).
  void submit_frame(const FrameConstants& frame);
  void finish_frame();
  // Zeroes the reference halves and the non-finite counter, and the DI sums.
  void reset_accumulation();
  // Realtime DI (RendererOptions::di): DiPipeline::frame/mean per chain.
  const DiPipeline& di() const;
  // The world cache (RendererOptions::world_cache); cache_view() is its
  // irradiance at each pixel's primary surface.
  const WorldCache& world_cache() const;
  // ReSTIR GI and specular GI (RendererOptions::gi).
  const GiPipeline& gi() const;
  bool has_gi() const { return gi_.has_value(); }
  // RendererOptions::frame_output: this frame's output image and measures.
  FrameOutput& frame_output();
  const FrameOutput& frame_output() const;
  // Hashes of buffer ranges on the GPU, one submission (between frames).
  std::vector<std::string> hash_buffers(const std::vector<HashRange>& ranges);
  // The same ranges hashed at the end of the next render_frame, inside its
  // submission (per-frame state hashes without a submission of their own);
  // frame_hashes() then holds them, in order, until the next such frame.
  void hash_after_next_frame(std::vector<HashRange> ranges) { next_frame_hashes_ = std::move(ranges); }
  const std::vector<std::string>& frame_hashes() const { return frame_hashes_; }
  Image cache_view() const { return world_cache().view(); }
  // The realtime output of one chain: DI, plus GI and specular when GI runs;
  // this frame's, or the temporal mean over the accumulation window.
  Image realtime_frame(std::uint32_t chain) const;
  Image realtime_mean(std::uint32_t chain) const;

  Image reference_mean() const;             // (A + B) / (nA + nB)
  Image reference_half(int which) const;    // 0 = A (even sample indices), 1 = B (odd), each its own mean
  std::uint64_t reference_nonfinite_samples() const;  // since the last reset
  // The raw accumulation buffer of half 0 (A) or 1 (B): rgb sum, w sample count per pixel.
  std::vector<glm::vec4> reference_sums(int which) const;
  // "albedo", "normal" (shading), "geometric_normal", "depth" (hit t, 0 = miss),
  // "motion" (xy pixels to the previous frame's position, z 1 if valid),
  // "position", "emissive", "material" (metallic, perceptual roughness, reflectance).
  Image gbuffer_layer(const std::string& name) const;
  static const std::vector<std::string>& gbuffer_layer_names();
  // Primary visibility decoded from the packed cluster IDs (as the G-buffer
  // resolve decodes them): (instance, primitive) per pixel, row-major from the
  // top left; (VISIBILITY_MISS, VISIBILITY_MISS) on a miss or an ID naming no
  // drawn triangle. Depth: hit t (0 on a miss).
  std::vector<glm::uvec2> visibility() const;
  // Raw: x the packed `cluster_id << triangle_bits | triangle`, y the
  // independent instance channel (core/clusters/cluster_ids.h).
  std::vector<glm::uvec2> packed_visibility() const;
  // The ID space (docs/design.md §8): each mesh's clusters and the bit split. Takes
  // effect at the next update_scene. Without it, each mesh's LOD-0 meshlets
  // (25/7 bits) own the IDs.
  void set_cluster_ids(std::vector<MeshClusterIds> meshes, const ClusterIdLayout& layout);
  const std::vector<std::uint32_t>& cluster_table() const { return cluster_table_; }
  std::vector<float> depth() const;

  // The last frame's pass times (the calibration kernel left out), and the
  // calibration kernel's own time (NaN when it is off).
  const std::vector<PassTiming>& last_timings() const { return pass_timings_; }
  double last_calibration_ms() const { return calibration_ms_; }
  // TLAS builds of either backend (ray-query TLAS or the BVH's CPU-built TLAS).
  std::uint32_t tlas_builds() const { return as_ ? as_->tlas_builds() : bvh_->tlas_builds(); }
  const RendererOptions& options() const { return options_; }

  // Captures, replay and the determinism check (gpu/state_buffers.h): every
  // buffer the enabled passes write or carry to the next frame, in a fixed
  // order (the determinism check names the first that differs), and the
  // passes' host-side state. Restore after update_scene() of the captured
  // frame's scene.
  void list_state(StateList& out);
  void save_host_state(HostState& out) const;
  void restore_host_state(const HostState& in);

 private:
  void ensure_buffer(Buffer& buffer, VkDeviceSize bytes, VkBufferUsageFlags usage, const char* name);
  void bind_passes();
  std::size_t pixel_count() const { return std::size_t(options_.width) * options_.height; }
  void require(bool enabled, const char* what) const;

  Device& device_;
  RendererOptions options_;
  Buffer vertices_, indices_;
  std::optional<AccelerationStructures> as_;  // rayquery backend
  std::optional<BvhBuffers> bvh_;             // bvh backend
  Buffer instances_, materials_, lights_, frame_;
  Buffer dfg_lut_;  // make_dfg_lut_buffer, once per renderer
  SceneTextureBuffers textures_;
  Buffer visibility_, depth_, gbuffer_;
  Buffer reference_a_, reference_b_, nonfinite_;
  std::optional<HostMirror> nonfinite_host_;  // copied at the end of each frame
  bool nonfinite_reset_ = false;              // zeroed since the last frame's copy
  std::optional<PrimaryVisibility> primary_visibility_;
  std::optional<GBufferResolve> gbuffer_resolve_;
  std::optional<ReferencePathTrace> reference_path_trace_;
  std::optional<DiPipeline> di_;
  std::optional<WorldCache> world_cache_;
  std::optional<GiPipeline> gi_;
  std::optional<FrameOutput> frame_output_;
  std::optional<BufferHash> state_hash_;  // made on the first hash_buffers or hash_after_next_frame
  std::vector<HashRange> next_frame_hashes_;
  std::vector<std::string> frame_hashes_;
  std::size_t submitted_hashes_ = 0;  // ranges the frame in flight hashes
  bool frame_in_flight_ = false;
  ShaderCompiler& compiler_;
  GpuTimer timer_;
  std::optional<TimingCalibration> calibration_;
  std::vector<PassTiming> pass_timings_;
  double calibration_ms_ = 0.0;
  // Packed visibility IDs: per-mesh clusters, the table the passes read.
  std::vector<MeshRange> mesh_ranges_;
  std::size_t triangle_count_ = 0;
  std::vector<MeshClusterIds> mesh_clusters_;
  ClusterIdLayout cluster_layout_;
  std::vector<std::uint32_t> cluster_table_;
  Buffer cluster_table_buffer_;
  Buffer previous_transforms_;  // mat4 per instance, the G-buffer's motion vectors
  bool scene_uploaded_ = false;
  bool bindings_dirty_ = true;
};

}  // namespace gi::gpu
