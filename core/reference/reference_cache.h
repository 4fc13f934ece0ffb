// On-disk cache of Embree references (docs/design.md §5): keyed by a hash of
// everything that determines the image, stored as a multi-layer EXR (layers
// mean, half_a, half_b) plus a JSON sidecar, both written then renamed.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

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

// The cached reference if one with this key exists in cache_dir, else the
// seed of that key copied into cache_dir (both *hit = true), else renders,
// stores and returns it (*hit = false). A corrupt or mismatching entry counts
// as a miss and is overwritten. `seconds` and `rays` of a hit are those of
// the original render.
ReferenceResult cached_reference(const Scene& scene, const ReferenceOptions& options,
                                 const std::filesystem::path& cache_dir, const std::filesystem::path& seed_dir,
                                 bool* hit);
// The same with the seeds of reference_seed_dir().
ReferenceResult cached_reference(const Scene& scene, const ReferenceOptions& options,
                                 const std::filesystem::path& cache_dir, bool* hit = nullptr);

// Seeds: cache entries committed with the baselines (reports/baselines/
// references), so that a fresh machine renders no reference the suite's
// baselines were judged against. The key names the integrator's sources and
// the Embree version, so a seed of another version is never read; Embree's
// output is the same at any thread count but was not shown to be the same on
// every CPU, so a seeded reference is the one the baselines saw, bit for bit.
// $GIHARNESS_REFERENCE_SEEDS (the nightly sets it to <baseline>/references
// for its scenarios), else the data folder's (core/data_dir.h); empty when
// there is none.
std::filesystem::path reference_seed_dir();

// The entries (file stems, "reference-<key>") this process used, read from
// the cache or the seeds or rendered, in first-use order. A run's summary
// lists its own (`reference_entries`).
std::vector<std::string> reference_entries_used();

struct ReferenceSeeds {
  std::size_t added = 0;    // entries copied into the seed folder now
  std::size_t removed = 0;  // seeds of another integrator version
  std::size_t entries = 0;  // the folder's entries after the update
  std::uint64_t bytes = 0;  // and their size
};

// Copies the entries `stems` names from cache_dir into seed_dir (each file
// written then renamed) unless they are there, and removes the seeds of
// another integrator version: none of them can be read again.
ReferenceSeeds keep_reference_seeds(const std::vector<std::string>& stems, const std::filesystem::path& cache_dir,
                                    const std::filesystem::path& seed_dir);

}  // namespace gi
