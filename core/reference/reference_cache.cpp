#include "core/reference/reference_cache.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>
#include <system_error>
#include <vector>

#include <unistd.h>

#include <embree3/rtcore.h>
#include <nlohmann/json.hpp>
#include <xxhash.h>

#include "core/atomic_file.h"
#include "core/data_dir.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/phase_clock.h"
#include "core/reference/reference_sources_hash.h"  // generated: core/reference/sources_hash.cmake
#include "core/scene_flatten.h"

namespace gi {
namespace {

// Bump when the reference changes in a way the hashed sources do not show.
constexpr const char* kReferenceTag = "giharness-embree-reference/1";

class Hasher {
 public:
  Hasher() : state_(XXH3_createState()) { XXH3_64bits_reset(state_); }
  ~Hasher() { XXH3_freeState(state_); }
  Hasher(const Hasher&) = delete;
  Hasher& operator=(const Hasher&) = delete;
  void bytes(const void* p, std::size_t n) { XXH3_64bits_update(state_, p, n); }
  template <class T>
  void pod(const T& v) {
    bytes(&v, sizeof(T));
  }
  template <class T>
  void array(const std::vector<T>& v) {  // length first: no ambiguity between arrays
    pod(std::uint64_t(v.size()));
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  void string(const std::string& s) {
    pod(std::uint64_t(s.size()));
    bytes(s.data(), s.size());
  }
  std::uint64_t digest() const { return XXH3_64bits_digest(state_); }

 private:
  XXH3_state_t* state_;
};

bool read_file(const std::filesystem::path& p, std::string& out) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return bool(in) || in.eof();
}

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::filesystem::path temp_sibling(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path t = path;
  t += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter.fetch_add(1));
  return t;
}

bool load(const std::filesystem::path& exr, const std::filesystem::path& json_path, std::uint64_t key,
          const std::string& version, const ReferenceOptions& o, ReferenceResult& out) {
  try {
    std::string text;
    if (!read_file(json_path, text)) return false;
    const nlohmann::json j = nlohmann::json::parse(text);
    if (j.at("key").get<std::string>() != hex64(key) || j.at("version").get<std::string>() != version) return false;
    std::map<std::string, Image> layers = read_exr(exr);
    for (const char* name : {"mean", "half_a", "half_b"}) {
      auto it = layers.find(name);
      if (it == layers.end() || it->second.width != o.width || it->second.height != o.height) return false;
    }
    out.mean = std::move(layers["mean"]);
    out.half_a = std::move(layers["half_a"]);
    out.half_b = std::move(layers["half_b"]);
    out.nonfinite_samples = j.at("nonfinite_samples").get<std::uint64_t>();
    out.seconds = j.at("seconds").get<double>();
    out.rays = j.at("rays").get<std::uint64_t>();
    return true;
  } catch (const std::exception&) {
    return false;  // corrupt or foreign entry: a miss
  }
}

std::mutex g_used_mutex;
std::vector<std::string> g_used;  // reference_entries_used()

void note_used(const std::string& stem) {
  const std::lock_guard lock(g_used_mutex);
  if (std::find(g_used.begin(), g_used.end(), stem) == g_used.end()) g_used.push_back(stem);
}

// An entry's two files from one folder into another, the EXR first and the
// sidecar last (an entry is complete once its JSON exists), each written
// then renamed.
void copy_entry(const std::string& stem, const std::filesystem::path& from, const std::filesystem::path& to) {
  std::filesystem::create_directories(to);
  for (const char* ext : {".exr", ".json"})
    write_atomically(to / (stem + ext), [&](const std::filesystem::path& tmp) {
      std::filesystem::copy_file(from / (stem + ext), tmp, std::filesystem::copy_options::overwrite_existing);
    });
}

// The integrator version an entry's sidecar names ("" when unreadable).
std::string entry_version(const std::filesystem::path& json_path) {
  try {
    std::string text;
    if (!read_file(json_path, text)) return "";
    return nlohmann::json::parse(text).value("version", "");
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace

const std::string& reference_integrator_version() {
  static const std::string version =
      std::string(kReferenceTag) + "+embree-" + RTC_VERSION_STRING + "+src-" + GIHARNESS_REFERENCE_SOURCES_HASH;
  return version;
}

std::uint64_t reference_cache_key(const Scene& scene, const ReferenceOptions& o) {
  const FlatGeometry g = flatten_geometry(scene);
  const FlatInstances f = flatten_instances(scene, g);
  const std::vector<std::uint8_t> visible = instance_visibility(scene);
  const GpuCamera camera = make_gpu_camera(scene.camera, std::max(o.width, 1u), std::max(o.height, 1u));
  Hasher h;
  h.string(reference_integrator_version());
  h.array(g.vertices);
  h.array(g.indices);
  h.array(g.meshes);
  h.array(f.instances);
  h.array(f.materials);
  h.array(f.lights);
  h.pod(f.directional_light_count);
  h.array(visible);
  h.pod(camera);
  for (std::uint32_t v : {o.width, o.height, o.spp, o.seed, o.max_bounces, o.first_sample}) h.pod(v);
  if (o.direct_only) h.string("direct_only");  // absent for path tracing: existing keys stay valid
  if (scene.background != glm::vec3(0.0f)) {    // absent when black, likewise
    h.string("background");
    h.pod(scene.background);
  }
  return h.digest();
}

std::filesystem::path reference_seed_dir() {
  if (const char* dir = std::getenv("GIHARNESS_REFERENCE_SEEDS"); dir && *dir) return dir;
  try {
    return data_dir() / "reports/baselines/references";
  } catch (const DataDirError&) {
    return {};
  }
}

std::vector<std::string> reference_entries_used() {
  const std::lock_guard lock(g_used_mutex);
  return g_used;
}

ReferenceResult cached_reference(const Scene& scene, const ReferenceOptions& o, const std::filesystem::path& cache_dir,
                                 bool* hit) {
  return cached_reference(scene, o, cache_dir, reference_seed_dir(), hit);
}

ReferenceResult cached_reference(const Scene& scene, const ReferenceOptions& o, const std::filesystem::path& cache_dir,
                                 const std::filesystem::path& seed_dir, bool* hit) {
  const PhaseScope timed(phase::kReferences);
  if (hit) *hit = false;
  const std::string& version = reference_integrator_version();

  const std::uint64_t key = reference_cache_key(scene, o);
  const std::string stem = "reference-" + hex64(key);
  note_used(stem);
  const std::filesystem::path exr = cache_dir / (stem + ".exr");
  const std::filesystem::path json_path = cache_dir / (stem + ".json");

  ReferenceResult r;
  if (load(exr, json_path, key, version, o, r)) {
    if (hit) *hit = true;
    return r;
  }
  if (!seed_dir.empty() && load(seed_dir / (stem + ".exr"), seed_dir / (stem + ".json"), key, version, o, r)) {
    copy_entry(stem, seed_dir, cache_dir);
    if (hit) *hit = true;
    return r;
  }

  r = render_reference(scene, o);
  std::filesystem::create_directories(cache_dir);
  // The EXR first, the sidecar last: an entry is complete once its JSON exists.
  write_exr(exr, {{"mean", &r.mean}, {"half_a", &r.half_a}, {"half_b", &r.half_b}});
  nlohmann::json j;
  j["key"] = hex64(key);
  j["version"] = version;
  j["scene"] = scene.name;
  j["width"] = o.width;
  j["height"] = o.height;
  j["spp"] = o.spp;
  j["seed"] = o.seed;
  j["max_bounces"] = o.max_bounces;
  j["first_sample"] = o.first_sample;
  j["direct_only"] = o.direct_only;
  j["nonfinite_samples"] = r.nonfinite_samples;
  j["seconds"] = r.seconds;
  j["rays"] = r.rays;
  const std::filesystem::path tmp = temp_sibling(json_path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << j.dump(2) << "\n";
    out.close();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error("reference cache: cannot write " + tmp.string());
    }
  }
  std::filesystem::rename(tmp, json_path);
  return r;
}

ReferenceSeeds keep_reference_seeds(const std::vector<std::string>& stems, const std::filesystem::path& cache_dir,
                                    const std::filesystem::path& seed_dir) {
  ReferenceSeeds out;
  for (const std::string& stem : stems) {
    if (std::filesystem::exists(seed_dir / (stem + ".json"))) continue;
    if (!std::filesystem::exists(cache_dir / (stem + ".json"))) continue;  // rendered by another process's cache
    copy_entry(stem, cache_dir, seed_dir);
    ++out.added;
  }
  if (!std::filesystem::is_directory(seed_dir)) return out;
  std::vector<std::filesystem::path> sidecars;
  for (const auto& e : std::filesystem::directory_iterator(seed_dir))
    if (e.path().extension() == ".json") sidecars.push_back(e.path());
  for (const std::filesystem::path& json_path : sidecars) {
    std::filesystem::path exr = json_path;
    exr.replace_extension(".exr");
    std::error_code ec;
    if (entry_version(json_path) != reference_integrator_version()) {
      std::filesystem::remove(json_path, ec);  // the sidecar first: a half-removed entry is a miss
      std::filesystem::remove(exr, ec);
      ++out.removed;
      continue;
    }
    ++out.entries;
    for (const std::filesystem::path& f : {json_path, exr}) {
      const std::uintmax_t size = std::filesystem::file_size(f, ec);
      if (!ec) out.bytes += size;
    }
  }
  return out;
}

}  // namespace gi
