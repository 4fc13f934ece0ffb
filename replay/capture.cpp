#include "replay/capture.h"

#include <fstream>
#include <map>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <xxhash.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/json_input.h"
#include "core/exr_io.h"
#include "core/npy.h"
#include "core/png_preview.h"
#include "core/shared/word_hash.h"
#include "gpu/renderer.h"
#include "gpu/state_layouts.h"

namespace gi {
namespace {

// "di/stored_reservoirs" → "di.stored_reservoirs.npy": flat folder, names stay readable.
std::string npy_file_name(const std::string& buffer_name) {
  std::string f = buffer_name;
  for (char& c : f)
    if (c == '/') c = '.';
  return f + ".npy";
}

std::vector<std::uint8_t> read_state_bytes(const gpu::StateBuffer& b) {
  std::vector<std::uint8_t> bytes(state_bytes(b));
  b.buffer->download_bytes(bytes.data(), bytes.size());
  return bytes;
}

// Validation of manifest.json: each accessor names the JSON path it expected.
class ManifestReader {
 public:
  explicit ManifestReader(std::string file) : file_(std::move(file)) {}
  const nlohmann::json& get(const nlohmann::json& j, const std::string& key, const std::string& path,
                            nlohmann::json::value_t type, const char* expected) const {
    if (!j.is_object() || !j.contains(key)) fail(path + "/" + key, std::string("a key \"") + key + "\": " + expected);
    const nlohmann::json& v = j[key];
    const bool ok = type == nlohmann::json::value_t::number_unsigned ? v.is_number_unsigned() : v.type() == type;
    if (!ok) fail(path + "/" + key, expected);
    return v;
  }
  [[noreturn]] void fail(const std::string& path, const std::string& expected) const {
    throw InputError(file_, path, expected);
  }

 private:
  std::string file_;
};

}  // namespace

std::filesystem::path capture_folder(std::uint32_t frame) { return fmt::format("captures/frame_{:05}", frame); }

std::filesystem::path capture_images_file(std::uint32_t frame) { return capture_folder(frame) / "images.exr"; }

std::string bytes_hash(const void* data, std::size_t bytes) { return shader::word_hash_bytes(data, bytes); }

std::string scene_hash(const FlatInstances& scene) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  XXH3_64bits_update(state, scene.instances.data(), scene.instances.size() * sizeof(GpuInstance));
  XXH3_64bits_update(state, scene.materials.data(), scene.materials.size() * sizeof(GpuMaterial));
  XXH3_64bits_update(state, scene.lights.data(), scene.lights.size() * sizeof(GpuLight));
  XXH3_64bits_update(state, &scene.directional_light_count, sizeof scene.directional_light_count);
  const std::string h = fmt::format("{:016x}", XXH3_64bits_digest(state));
  XXH3_freeState(state);
  return h;
}

std::size_t state_bytes(const gpu::StateBuffer& b) {
  std::uint64_t n = npy_itemsize(b.dtype);
  for (std::uint64_t d : b.shape) n *= d;
  if (b.buffer == nullptr || n > b.buffer->size())
    throw DeviceError(fmt::format("state buffer {}: shape needs {} bytes, the buffer has {}", b.name, n,
                                  b.buffer ? b.buffer->size() : 0));
  return static_cast<std::size_t>(n);
}

std::vector<gpu::HashRange> state_ranges(const gpu::StateList& state) {
  std::vector<gpu::HashRange> ranges;
  for (const gpu::StateBuffer& b : state) ranges.push_back({b.buffer, state_bytes(b)});
  return ranges;
}

nlohmann::json hash_record(std::uint32_t frame, const gpu::StateList& state, const std::vector<std::string>& hashes) {
  if (hashes.size() != state.size())
    throw DeviceError(fmt::format("hash_record: {} hashes for {} state buffers", hashes.size(), state.size()));
  nlohmann::json buffers = nlohmann::json::array();
  for (std::size_t i = 0; i < state.size(); ++i) buffers.push_back({state[i].name, hashes[i]});
  return {{"frame", frame}, {"buffers", buffers}};
}

void write_capture(const std::filesystem::path& dir, nlohmann::json manifest, gpu::Renderer& renderer,
                   const std::vector<std::pair<std::string, const Image*>>& layers, const Image& preview) {
  gpu::StateList state;
  renderer.list_state(state);
  nlohmann::json buffers = nlohmann::json::array();
  for (const gpu::StateBuffer& b : state) {
    const std::vector<std::uint8_t> bytes = read_state_bytes(b);
    const std::string file = npy_file_name(b.name);
    write_npy(dir / file, b.dtype, b.shape, bytes.data(), bytes.size());
    buffers.push_back({{"name", b.name},
                       {"file", file},
                       {"dtype", b.dtype},
                       {"shape", b.shape},
                       {"layout", b.layout},
                       {"bytes", bytes.size()},
                       {"hash", bytes_hash(bytes.data(), bytes.size())}});
    // The struct's fields (gpu/state_layouts.h), so a reader names them without
    // a table of its own: share/giharness/python/giharness_capture.py, inspect.
    if (nlohmann::json fields = gpu::layout_fields_json(b.layout); !fields.is_null()) buffers.back()["fields"] = fields;
  }
  gpu::HostState host;
  renderer.save_host_state(host);
  nlohmann::json host_json = nlohmann::json::array();
  for (const gpu::HostStateEntry& e : host) host_json.push_back({{"name", e.name}, {"words", e.words}});

  nlohmann::json layer_names = nlohmann::json::array();
  for (const auto& [name, image] : layers) layer_names.push_back(name.empty() ? "(R,G,B)" : name);
  write_exr(dir / "images.exr", layers);
  write_png_preview(dir / "images.png", preview);

  manifest["schema_version"] = 1;
  manifest["hash_scheme"] = shader::WORD_HASH_SCHEME;
  manifest["buffers"] = buffers;
  manifest["host_state"] = host_json;
  manifest["images"] = {{"file", "images.exr"}, {"layers", layer_names}, {"preview", "images.png"}};
  manifest["run_hashes"] = "run_hashes.jsonl";
  write_json_file(dir / "manifest.json", manifest);
}

void attach_run_hashes(const std::filesystem::path& capture_dir, const std::filesystem::path& hash_log) {
  write_atomically(capture_dir / "run_hashes.jsonl", [&](const std::filesystem::path& tmp) {
    std::filesystem::copy_file(hash_log, tmp, std::filesystem::copy_options::overwrite_existing);
  });
}

Capture read_capture(const std::filesystem::path& dir) {
  using vt = nlohmann::json::value_t;
  const std::filesystem::path file = dir / "manifest.json";
  Capture c;
  c.dir = dir;
  c.manifest = read_json_input(file, "a capture folder with a manifest.json (giharness run --capture F)");
  const ManifestReader r(file.string());
  const nlohmann::json& m = c.manifest;
  if (!m.is_object()) r.fail("", "a JSON object");
  c.frame = r.get(m, "frame", "", vt::number_unsigned, "the captured frame, an unsigned integer").get<std::uint32_t>();
  r.get(m, "frames", "", vt::number_unsigned, "the run's frame count, an unsigned integer");
  r.get(m, "seed", "", vt::number_unsigned, "the seed, an unsigned integer");
  r.get(r.get(m, "scenario", "", vt::object, "an object"), "document", "/scenario", vt::object,
        "the scenario document, an object");
  r.get(m, "loop", "", vt::object, "the frame loop's state, an object");
  const nlohmann::json& buffers = r.get(m, "buffers", "", vt::array, "an array of buffers");
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    const std::string p = fmt::format("/buffers/{}", i);
    for (const char* key : {"name", "file", "dtype", "hash"}) r.get(buffers[i], key, p, vt::string, "a string");
    r.get(buffers[i], "shape", p, vt::array, "an array of unsigned integers");
  }
  c.hash_scheme = m.value("hash_scheme", std::string(shader::XXH3_HASH_SCHEME));
  if (c.hash_scheme != shader::WORD_HASH_SCHEME && c.hash_scheme != shader::XXH3_HASH_SCHEME)
    r.fail("/hash_scheme", fmt::format("\"{}\" or \"{}\"", shader::WORD_HASH_SCHEME, shader::XXH3_HASH_SCHEME));
  const nlohmann::json& host = r.get(m, "host_state", "", vt::array, "an array of {name, words}");
  for (std::size_t i = 0; i < host.size(); ++i) {
    r.get(host[i], "name", fmt::format("/host_state/{}", i), vt::string, "a string");
    r.get(host[i], "words", fmt::format("/host_state/{}", i), vt::array, "an array of 32-bit words");
  }
  return c;
}

std::string capture_bytes_hash(const Capture& capture, const void* data, std::size_t bytes) {
  if (capture.hash_scheme == shader::XXH3_HASH_SCHEME) return fmt::format("{:016x}", XXH3_64bits(data, bytes));
  return bytes_hash(data, bytes);
}

void restore_capture(const Capture& capture, gpu::Renderer& renderer) {
  const std::string manifest_file = (capture.dir / "manifest.json").string();
  std::map<std::string, const nlohmann::json*> by_name;
  const nlohmann::json& buffers = capture.manifest["buffers"];
  for (const nlohmann::json& b : buffers) by_name[b["name"].get<std::string>()] = &b;

  gpu::StateList state;
  renderer.list_state(state);
  if (state.size() != buffers.size()) {
    std::string listed;
    for (const gpu::StateBuffer& b : state) listed += (listed.empty() ? "" : ", ") + b.name;
    throw InputError(manifest_file, "/buffers",
                     fmt::format("the {} buffers this pipeline has ({}), the capture has {}", state.size(), listed,
                                 buffers.size()));
  }
  for (const gpu::StateBuffer& b : state) {
    const auto it = by_name.find(b.name);
    if (it == by_name.end()) throw InputError(manifest_file, "/buffers", "a buffer named \"" + b.name + "\"");
    const nlohmann::json& entry = *it->second;
    const std::filesystem::path file = capture.dir / entry["file"].get<std::string>();
    const NpyArray a = read_npy(file);
    if (a.dtype != b.dtype || a.shape != b.shape)
      throw InputError(file.string(), "",
                       fmt::format("dtype {} and shape {} as this pipeline's {} (got {} {})", b.dtype,
                                   nlohmann::json(b.shape).dump(), b.name, a.dtype, nlohmann::json(a.shape).dump()));
    if (capture_bytes_hash(capture, a.data.data(), a.data.size()) != entry["hash"].get<std::string>())
      spdlog::warn("{}: bytes differ from the manifest's hash {} (edited after the capture?); restoring them anyway",
                   file.string(), entry["hash"].get<std::string>());
    b.buffer->upload_bytes(a.data.data(), a.data.size());
  }
  gpu::HostState host;
  for (const nlohmann::json& e : capture.manifest["host_state"])
    host.push_back({e["name"].get<std::string>(), e["words"].get<std::vector<std::uint32_t>>()});
  try {
    renderer.restore_host_state(host);
  } catch (const std::invalid_argument& e) {
    throw InputError(manifest_file, "/host_state", e.what());
  }
}

}  // namespace gi
