#include "app/inspect_command.h"

#include <chrono>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <glm/gtc/packing.hpp>

#include "app/capture_cells.h"
#include "checks/reference_check.h"
#include "core/atomic_file.h"
#include "core/cache_root.h"
#include "core/errors.h"
#include "core/exr_io.h"
#include "core/json_input.h"
#include "core/npy.h"
#include "core/profile.h"
#include "core/reference/reference_cache.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "core/scene_events.h"
#include "core/shared/word_hash.h"
#include "gpu/realtime_settings.h"
#include "replay/capture.h"
#include "reports/capture_diff.h"
#include "reports/inspect_page.h"

namespace gi {

CLI::App* add_inspect_subcommand(CLI::App& app, InspectOptions& o) {
  CLI::App* cmd = app.add_subcommand("inspect", "one self-contained HTML page of a capture: every layer and buffer "
                                                "as a picture, a pixel decoded, the comparison with another capture");
  cmd->add_option("capture", o.capture, "capture folder (out/captures/frame_NNNNN)")->required();
  cmd->add_option("--against", o.against,
                  "another capture of the same frame (a replay's, another profile's): buffer by buffer, equal or "
                  "different, the differing elements and the first; or a baseline JSON "
                  "(reports/baselines/<class>/<scenario>.json): each buffer by hash, the output against its final "
                  "image when the capture is of the last frame");
  cmd->add_flag("--reference", o.reference,
                "the Embree reference of the captured frame beside the output (rendered, or read from the reference "
                "cache a run's checks fill)");
  cmd->add_option("--reference-spp", o.reference_spp,
                  "the reference's samples per pixel (default: the scenario's reference check's, else 256)")
      ->check(CLI::Range(2u, 1u << 20));
  cmd->add_option("--out", o.out, "the page (default <capture>/inspect.html)");
  return cmd;
}

CaptureData load_capture_data(const std::filesystem::path& dir) {
  const Capture capture = read_capture(dir);
  CaptureData d;
  d.dir = dir;
  d.manifest = capture.manifest;
  d.frame = capture.frame;
  const std::string manifest_file = (dir / "manifest.json").string();
  const nlohmann::json& buffers = d.manifest["buffers"];
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    const nlohmann::json& b = buffers[i];
    const std::string path = fmt::format("/buffers/{}", i);
    if (!b.is_object() || !b.contains("name") || !b["name"].is_string() || !b.contains("file") || !b["file"].is_string())
      throw InputError(manifest_file, path, "a buffer with a \"name\" and a \"file\" (strings)");
    NpyArray a = read_npy(dir / b["file"].get<std::string>());
    CaptureBuffer cb;
    cb.name = b["name"];
    cb.dtype = a.dtype;
    cb.shape = a.shape;
    cb.layout = b.value("layout", std::string());
    cb.fields = b.contains("fields") ? b["fields"] : nlohmann::json();
    cb.bytes = std::move(a.data);
    d.buffers.push_back(std::move(cb));
  }
  // The EXR's unnamed R,G,B layer is the output.
  for (auto& [name, image] : read_exr(dir / "images.exr")) {
    CaptureLayer l{name.empty() ? "output" : name, std::move(image)};
    if (l.name == "output") d.layers.insert(d.layers.begin(), std::move(l));
    else d.layers.push_back(std::move(l));
  }
  if (d.layers.empty()) throw InputError((dir / "images.exr").string(), "", "an EXR with at least the output layer");
  d.width = d.layers.front().image.width;
  d.height = d.layers.front().image.height;
  return d;
}

namespace {

// The capture's scenario, re-derived from its manifest (what the run read).
Scenario manifest_scenario(const CaptureData& c) {
  const nlohmann::json& m = c.manifest;
  return parse_scenario(m["scenario"]["document"], m["scenario"].value("file", std::string("manifest.json")));
}

// The Embree reference of the captured frame at the capture's resolution and
// the run's seed, through the reference cache: the key is the scene, camera
// and options, so the reference a run's check rendered at this spp is read,
// not rendered again (`giharness reference` takes the same path).
Image capture_reference(const CaptureData& c, std::optional<std::uint32_t> spp_option, std::string& note) {
  const nlohmann::json& m = c.manifest;
  const Scenario scenario = manifest_scenario(c);
  std::optional<std::string> profile;
  if (m.contains("profile_option") && m["profile_option"].is_string()) profile = m["profile_option"].get<std::string>();
  Scene initial = build_scene(scenario);
  apply_material_model(initial, resolve_profile(scenario, profile, m.value("sets", std::vector<std::string>{})));
  const Scene scene = scene_at_frame(initial, scenario, c.frame);
  ReferenceOptions options;
  options.width = c.width;
  options.height = c.height;
  options.seed = m.value("seed", scenario.seed);
  options.spp = spp_option.value_or(scenario_reference_spp(scenario, 256));
  bool hit = false;
  const auto start = std::chrono::steady_clock::now();
  ReferenceResult r = cached_reference(scene, options, cache_root() / "reference", &hit);
  note = fmt::format("Embree reference of frame {} at {} spp, seed {} ({})", c.frame, options.spp, options.seed,
                     hit ? "from the reference cache" : "rendered now");
  spdlog::info("inspect: reference of frame {} at {} spp: {} in {:.1f} s", c.frame, options.spp,
               hit ? "cached" : "rendered", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return std::move(r.mean);
}

struct BaselineSide {
  nlohmann::json json;
  Image image;            // the final image, when the capture is of the last frame
  Image output_half;      // the capture's output rounded as the baseline stores its image
  bool has_image = false;
  std::string image_note;
};

// A baseline JSON (reports/baselines/<class>/<scenario>.json): its buffers'
// final hashes, and its final image when the capture is of the scenario's last frame.
BaselineSide read_baseline(const std::filesystem::path& file, const CaptureData& c) {
  BaselineSide b;
  b.json = read_json_input(file, "a baseline JSON (reports/baselines/<class>/<scenario>.json)");
  const std::string f = file.string();
  if (!b.json.is_object() || !b.json.contains("hashes") || !b.json["hashes"].is_object() ||
      !b.json["hashes"].contains("final_buffers") || !b.json["hashes"]["final_buffers"].is_object())
    throw InputError(f, "/hashes/final_buffers", "an object of buffer name to hash (a baseline's final buffer hashes)");
  for (const auto& [name, hash] : b.json["hashes"]["final_buffers"].items())
    if (!hash.is_string()) throw InputError(f, "/hashes/final_buffers/" + name, "a hash (a string)");
  const std::string scheme = b.json["hashes"].value("scheme", std::string(shader::WORD_HASH_SCHEME));
  if (scheme != shader::WORD_HASH_SCHEME)
    throw InputError(f, "/hashes/scheme", fmt::format("the hash scheme \"{}\" (this build hashes buffers so)",
                                                      shader::WORD_HASH_SCHEME));
  const std::string scenario = c.manifest["scenario"].value("name", std::string());
  if (b.json.contains("scenario") && b.json["scenario"].is_string() && b.json["scenario"] != scenario)
    throw InputError(f, "/scenario", fmt::format("the capture's scenario \"{}\"", scenario));
  const std::uint32_t frames = c.manifest.value("frames", 0u);
  if (frames == 0 || c.frame + 1 != frames) {
    b.image_note = fmt::format("The capture is of frame {}; the baseline's image is of the scenario's last frame {}: "
                               "the output is not compared (a capture of the last frame is).",
                               c.frame, frames ? std::to_string(frames - 1) : std::string("?"));
    return b;
  }
  if (!b.json.contains("image") || !b.json["image"].is_string())
    throw InputError(f, "/image", "the baseline's final image, an EXR file name beside the JSON");
  auto layers = read_exr(file.parent_path() / b.json["image"].get<std::string>());
  const auto it = layers.find("");
  if (it == layers.end())
    throw InputError((file.parent_path() / b.json["image"].get<std::string>()).string(), "", "an EXR with an unnamed R,G,B layer");
  b.image = std::move(it->second);
  // The baseline stores half floats: both sides at that precision, as the
  // nightly's exact comparison reads them (reports/change.h).
  b.output_half = c.layers.front().image;
  for (glm::vec3& p : b.output_half.pixels)
    for (int k = 0; k < 3; ++k) p[k] = glm::unpackHalf1x16(glm::packHalf1x16(p[k]));
  b.has_image = true;
  return b;
}

// The region's mask: a layer of an EXR a check wrote (1 inside), one byte a pixel.
std::vector<std::uint8_t> region_mask(const std::filesystem::path& file, const std::string& layer, std::uint32_t w,
                                      std::uint32_t h) {
  auto layers = read_exr(file);
  const auto it = layers.find(layer);
  if (it == layers.end()) throw InputError(file.string(), "", fmt::format("an EXR with the layer \"{}\"", layer));
  if (it->second.width != w || it->second.height != h)
    throw InputError(file.string(), "", fmt::format("the layer \"{}\" at the capture's {}x{}", layer, w, h));
  std::vector<std::uint8_t> mask(it->second.pixels.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = it->second.pixels[i].x > 0.5f ? 1 : 0;
  return mask;
}

}  // namespace

std::uintmax_t write_inspect_page(const std::filesystem::path& capture, const InspectExtras& x,
                                  const std::filesystem::path& out) {
  const CaptureData here = load_capture_data(capture);
  CaptureDerivation derived = derive_from_capture(here);
  InspectPageInputs in;
  in.capture = &here;
  in.derived = std::move(derived.buffers);
  in.derived_notes = std::move(derived.buffer_notes);
  in.notes = std::move(derived.notes);
  in.lights = derived.lights;
  in.region = x.region;
  if (!x.region_mask_file.empty()) in.region_mask = region_mask(x.region_mask_file, x.region_mask_layer, here.width, here.height);
  Image reference;
  std::string reference_note;
  if (x.reference) {
    reference = capture_reference(here, x.reference_spp, reference_note);
    in.extra_layers.push_back({"reference/output", "reference", reference_note, &reference});
  }
  CaptureData there;
  CaptureDiff diff;
  BaselineSide baseline;
  if (!x.against.empty() && std::filesystem::is_regular_file(x.against)) {
    baseline = read_baseline(x.against, here);
    std::map<std::string, std::string> hashes;
    for (const CaptureBuffer& b : here.buffers) hashes[b.name] = bytes_hash(b.bytes.data(), b.bytes.size());
    diff = diff_against_baseline(here, baseline.json, hashes, baseline.has_image ? &baseline.output_half : nullptr,
                                 baseline.has_image ? &baseline.image : nullptr, baseline.image_note);
    in.diff = &diff;
    in.against_label = x.against.string();
    if (baseline.has_image)
      in.extra_layers.push_back({"baseline/output", "baseline", "the baseline's final image (half floats)", &baseline.image});
  } else if (!x.against.empty()) {
    there = load_capture_data(x.against);
    diff = diff_captures(here, there);
    in.against = &there;
    in.diff = &diff;
  }
  const std::string page = inspect_page(in);
  if (!out.parent_path().empty()) std::filesystem::create_directories(out.parent_path());
  write_text_file(out, page);
  return page.size();
}

int run_inspect(const InspectOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::filesystem::path out = o.out.empty() ? o.capture / "inspect.html" : o.out;
  InspectExtras extras;
  extras.against = o.against;
  extras.reference = o.reference;
  extras.reference_spp = o.reference_spp;
  const std::uintmax_t bytes = write_inspect_page(o.capture, extras, out);
  spdlog::info("inspect: {} ({:.1f} MB) in {:.1f} s", out.string(), double(bytes) / 1e6,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace gi
