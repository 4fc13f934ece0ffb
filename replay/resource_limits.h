// Limits checked before a scenario touches the GPU, each a clear InputError
// (exit 2) naming the scenario file and the JSON path that asks too much:
// triangles, lights, and the memory its buffers would need on this device.
#pragma once
#include <cstdint>

#include "core/scenario.h"
#include "core/scene.h"

namespace gi {

inline constexpr std::uint64_t kMaxTriangles = 1ull << 26;  // 64 M: index buffers stay below 1 GiB
inline constexpr std::uint64_t kMaxLights = 1ull << 24;     // light ids are packed in 24 bits

// A generous upper bound of the GPU bytes one pixel needs across every pass
// (visibility, depth, G-buffer, reference sums, two DI chains of reservoirs,
// outputs and accumulations), and per triangle (vertices, indices, BLAS/BVH).
inline constexpr std::uint64_t kBytesPerPixel = 1024;
inline constexpr std::uint64_t kBytesPerTriangle = 256;

std::uint64_t estimated_gpu_bytes(const Scenario& scenario, const Scene& scene);

// The texels of every image, RGBA8 in one storage buffer (core/shared/texture_sampling.h).
std::uint64_t texel_bytes(const Scene& scene);

// Throws InputError when the scene or the resolution is over a limit;
// heap_bytes = 0 skips the memory check and storage_range = 0 the texel
// buffer's (no device yet).
void check_resource_limits(const Scenario& scenario, const Scene& scene, std::uint64_t heap_bytes,
                           std::uint64_t storage_range = 0);

}  // namespace gi
