// Frame captures (docs/design.md §9): a folder per captured frame,
//
//   <out>/captures/frame_00060/
//     manifest.json      the run (scenario document, frame, frames, seed, profile, --set values,
//                        backend, device, driver), the loop's state, the passes' host state,
//                        and every buffer: file, dtype, shape, layout, hash of its bytes (bytes_hash)
//                        and, where the layout is a struct, its fields (gpu/state_layouts.h)
//     images.exr         multi-layer: output (R,G,B), di/half_a/half_b, albedo, normal, depth, motion
//     images.png         preview of the output
//     <buffer>.npy       every buffer Renderer::list_state gives ("di/stored_reservoirs" →
//                        di.stored_reservoirs.npy), the persistent ones and this frame's outputs
//     run_hashes.jsonl   the capturing run's per-frame buffer hashes (copied when it ends),
//                        what `replay --verify` compares against
//
// The scene is not stored: events are a pure function of (initial scene,
// scenario, frame) (core/scene_events.h), so a replay re-derives the scene at the
// captured frame from the scenario document in the manifest, and checks it
// against the manifest's scene hash. Random numbers derive from (seed, frame,
// pixel) only: there is no RNG state beyond the frame index.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/scene_flatten.h"
#include "gpu/passes/buffer_hash.h"
#include "gpu/state_buffers.h"

namespace gi {

namespace gpu {
class Renderer;
}

// "captures/frame_00060" (relative to a run's out dir).
std::filesystem::path capture_folder(std::uint32_t frame);
// The capture's images relative to a run's out dir: "captures/frame_00060/images.exr".
std::filesystem::path capture_images_file(std::uint32_t frame);

// The harness's buffer hash of the bytes, 16 hex digits (core/shared/word_hash.h):
// the hash in manifests and hash logs, equal to the GPU's for the same bytes
// (gpu/passes/buffer_hash.h), so a captured buffer's file checks against the run's log.
std::string bytes_hash(const void* data, std::size_t bytes);
// Bytes of a listed buffer that its dtype and shape cover.
std::size_t state_bytes(const gpu::StateBuffer& b);
// Hash of the scene as uploaded (instances, materials, lights): a replay
// re-derives the scene from the events and checks it against the manifest's.
std::string scene_hash(const FlatInstances& scene);
// The ranges a hash of the listed buffers covers (state_bytes of each).
std::vector<gpu::HashRange> state_ranges(const gpu::StateList& state);
// {"frame": f, "buffers": [[name, hash], …]} in list order, from hashes of
// state_ranges(state) made on the GPU (nothing read back).
nlohmann::json hash_record(std::uint32_t frame, const gpu::StateList& state, const std::vector<std::string>& hashes);

// Writes the folder `dir`. `manifest` holds the run's fields (run_scenario
// fills them); buffers, host state and images are added here. manifest.json
// is written last, so a folder without one is an incomplete capture.
void write_capture(const std::filesystem::path& dir, nlohmann::json manifest, gpu::Renderer& renderer,
                   const std::vector<std::pair<std::string, const Image*>>& layers, const Image& preview);

// Copies the run's finished hash log into the capture as run_hashes.jsonl
// (captures are self-contained: a folder moved elsewhere still verifies).
void attach_run_hashes(const std::filesystem::path& capture_dir, const std::filesystem::path& hash_log);

struct Capture {
  std::filesystem::path dir;
  nlohmann::json manifest;
  std::uint32_t frame = 0;
  // The hash of its manifest and run_hashes.jsonl: "gi-word-hash-v1", or
  // "xxh3-64" for captures written before the GPU hashed (2026-12-03).
  std::string hash_scheme;
};

// A capture's .npy bytes hashed as its manifest's scheme did.
std::string capture_bytes_hash(const Capture& capture, const void* data, std::size_t bytes);

// Reads and validates manifest.json (gi::InputError naming the file, the
// JSON path and the expectation).
Capture read_capture(const std::filesystem::path& dir);

// Uploads every buffer the renderer lists from the capture's .npy files and
// restores the host state. The renderer must list exactly the capture's
// buffers with the same dtype and shape (else InputError). A file whose
// bytes no longer match the manifest's hash is restored anyway, with a
// warning: `replay --verify` then names where the run diverges.
void restore_capture(const Capture& capture, gpu::Renderer& renderer);

}  // namespace gi
