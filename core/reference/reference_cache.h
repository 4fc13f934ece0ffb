// On-disk cache of Embree references (DESIGN §5): keyed by a hash of
// everything that determines the image, stored as a multi-layer EXR (layers
// mean, half_a, half_b) plus a JSON sidecar, both written then renamed.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/reference/embree_reference.h"
#include "core/scene.h"

namespace gi {

// The integrator version folded into every key: a fixed tag (bump it by hand
// for changes outside the hashed files), the Embree version, and a hash of
// core/shared/*.h and core/reference/embree_*.{h,cpp} taken at build time
// (core/CMakeLists.txt, core/reference/sources_hash.cmake): the sources this
// binary's integrator was compiled from, with no source tree at run time.
const std::string& reference_integrator_version();

// XXH3-64 over the flattened scene (geometry, instances, materials, lights,
// visibility), the GPU camera at the options' resolution, the options except
// `threads`, and reference_integrator_version().
std::uint64_t reference_cache_key(const Scene& scene, const ReferenceOptions& options);

// The cached reference if one with this key exists in cache_dir (*hit = true),
// else renders, stores and returns it (*hit = false). A corrupt or mismatching
// entry counts as a miss and is overwritten. `seconds` and `rays` of a hit are
// those of the original render.
ReferenceResult cached_reference(const Scene& scene, const ReferenceOptions& options,
                                 const std::filesystem::path& cache_dir, bool* hit = nullptr);

}  // namespace gi
