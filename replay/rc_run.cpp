#include "replay/rc_run.h"

#include <algorithm>
#include <chrono>
#include <map>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/phase_clock.h"
#include "core/exr_io.h"
#include "core/json_input.h"
#include "core/profile.h"
#include "core/rc/rc_reference.h"
#include "core/rc/rc_settings.h"
#include "core/scene.h"
#include "core/shared/word_hash.h"
#include "gpu/device.h"
#include "gpu/passes/buffer_hash.h"
#include "gpu/profile_keys.h"
#include "gpu/rc/rc_pipeline.h"
#include "gpu/shader_compiler.h"
#include "gpu/timer.h"
#include "replay/capture.h"
#include "checks/check_registry.h"
#include "replay/frame_log.h"
#include "replay/run_summary.h"
#include "replay/wall_breakdown.h"
#include "reports/change.h"
#include "reports/summary.h"

namespace gi {
namespace {

struct RcCheck {
  std::unique_ptr<Check> check;
  CheckNeeds needs;
};

// The reference of each canvas a judged frame shows, computed once.
class ReferenceCache {
 public:
  explicit ReferenceCache(RcReferenceOptions options) : options_(options) {}
  const RcReference& get(const Canvas& canvas) {
    auto [it, fresh] = cache_.try_emplace(canvas.hash());
    if (fresh) {
      it->second = rc_reference(canvas, options_);
      spdlog::debug("rc reference: {} rays per pixel in {:.2f} s", it->second.rays, it->second.seconds);
    }
    return it->second;
  }

 private:
  RcReferenceOptions options_;
  std::map<std::uint64_t, RcReference> cache_;
};

Image grey(const std::vector<float>& v, std::uint32_t w, std::uint32_t h) {
  Image img(w, h);
  for (std::size_t i = 0; i < v.size(); ++i) img.pixels[i] = glm::vec3(v[i]);
  return img;
}

// captures/frame_NNNNN/images.exr (output, scene, distance, cascade_<c> for
// each cascade after its merge) and mipmap.exr, and what they were made of.
void write_capture(const std::filesystem::path& out, std::uint32_t frame, gpu::Device& device,
                   gpu::RcPipeline& pipeline, const Canvas& canvas, const std::string& image_hash,
                   const nlohmann::json& run) {
  const RcSettings& s = pipeline.settings();
  std::map<std::uint32_t, Image> cascades;
  std::vector<gpu::Buffer> copies;
  for (std::uint32_t c = 0; c < s.cascades; ++c)
    copies.emplace_back(device, VkDeviceSize(s.width) * s.height * 16,
                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                            VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                        "rc_capture_cascade");
  // The frame again, copying each cascade out after its pass (bit-identical:
  // nothing carries between frames).
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    pipeline.record(cmd, nullptr, [&](VkCommandBuffer c, std::uint32_t cascade, const gpu::Buffer& b) {
      VkBufferCopy region{0, 0, b.size()};
      vkCmdCopyBuffer(c, b.handle(), copies[cascade].handle(), 1, &region);
      gpu::compute_barrier(c);
    });
  });
  for (std::uint32_t c = 0; c < s.cascades; ++c) cascades[c] = gpu::rc_image(copies[c], s.width, s.height);
  const Image output = pipeline.output(), scene = pipeline.scene(), mip = pipeline.mipmap();
  const Image distance = grey(pipeline.distance(), s.width, s.height);
  std::vector<std::pair<std::string, const Image*>> layers = {{"", &output}, {"scene", &scene}, {"distance", &distance}};
  for (const auto& [c, img] : cascades) layers.push_back({fmt::format("cascade_{}", c), &img});
  const std::filesystem::path dir = out / capture_folder(frame);
  std::filesystem::create_directories(dir);
  write_exr(dir / "images.exr", layers);
  write_exr(dir / "mipmap.exr", {{"", &mip}});
  write_json_file(dir / "manifest.json", {{"frame", frame},
                                          {"pipeline", "radiance_cascades"},
                                          {"image_hash", image_hash},
                                          {"run", run},
                                          {"settings", s.to_json()},
                                          {"canvas", canvas.to_json()},
                                          {"output_hash", bytes_hash(output.pixels.data(), output.pixels.size() * sizeof(glm::vec3))},
                                          {"layers", "images.exr: output (R,G,B), scene, distance (grey, pixels), "
                                                     "cascade_<c> (each cascade after merging the coarser ones); "
                                                     "mipmap.exr: one texel per cascade-0 probe"}});
}

}  // namespace

RunResult run_rc_scenario(const Scenario& scenario, const RunOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const std::map<std::string, double> phases_at_start = phase_seconds();
  Profile profile = resolve_profile(scenario, options.profile, options.sets);
  if (!profile_has_family(profile, ProfileFamily::radiance_cascades))
    throw InputError("--profile", "", "the radiance-cascades profile (radiance-cascades-lesson or a file with its keys)");
  const Canvas& initial = *scenario.canvas;
  const RcSettings settings = rc_settings(profile, initial.width, initial.height);
  const std::uint32_t frames = options.frames.value_or(scenario.frames);
  const std::uint32_t seed = options.seed.value_or(scenario.seed);
  std::filesystem::create_directories(options.out_dir);

  static const Scene kNoScene;  // a canvas has none; CheckContext asks for one
  std::vector<RcCheck> checks;
  for (const CheckSpec& spec : scenario.checks) {
    CheckContext ctx{scenario, spec, profile, options, kNoScene, frames, seed};
    RcCheck c;
    c.check = make_check(ctx);
    c.needs = c.check->needs();
    checks.push_back(std::move(c));
  }
  std::set<std::uint32_t> captures(scenario.capture.begin(), scenario.capture.end());
  captures.insert(options.capture.begin(), options.capture.end());
  for (const RcCheck& c : checks) captures.insert(c.needs.captures.begin(), c.needs.captures.end());

  gpu::Device device(options.device, gpu::parse_backend_request(options.backend));
  gpu::ShaderCompiler compiler;
  gpu::RcPipeline pipeline(device, compiler, settings);
  gpu::GpuTimer timer(device);
  gpu::BufferHash hasher(device, compiler, 1);
  const gpu::RcBuffers& b = pipeline.buffers();
  const VkDeviceSize pixels = VkDeviceSize(settings.width) * settings.height;
  ReferenceCache references({.rays = 1024, .seed = seed});

  // A replay (app/replay_command.cpp) starts at the captured frame
  // itself: nothing carries between frames, so rendering it again is the
  // proof that the bits are the same (its hash against the manifest's).
  std::uint32_t first_frame = 0;
  std::string resumed_hash;
  if (!options.resume_from.empty()) {
    const nlohmann::json m = read_json_input(options.resume_from / "manifest.json", "an RC capture's manifest");
    first_frame = m.at("frame").get<std::uint32_t>();
    resumed_hash = m.at("image_hash").get<std::string>();
    if (first_frame >= frames)
      throw InputError((options.resume_from / "manifest.json").string(), "/frame",
                       fmt::format("a captured frame below the run's {} frames", frames));
  }
  const nlohmann::json run_facts = {
      {"scenario", {{"file", scenario.file.string()}, {"document", scenario.raw}}},
      {"frames", frames},
      {"seed", seed},
      {"sets", options.sets},
      {"profile_option", options.profile ? nlohmann::json(*options.profile) : nlohmann::json(nullptr)},
      {"backend", gpu::backend_name(device.backend())}};

  FrameLog log(options.out_dir / "frames.jsonl");
  std::vector<double> wall_ms;
  std::vector<std::string> image_hashes;
  std::optional<std::uint64_t> uploaded;
  Image last;
  std::optional<PhaseScope> frames_timed;
  frames_timed.emplace(phase::kFrames);
  for (std::uint32_t f = first_frame; f < frames; ++f) {
    const auto t0 = std::chrono::steady_clock::now();
    const Canvas canvas = canvas_at_frame(initial, scenario, f);
    if (const std::uint64_t h = canvas.hash(); uploaded != h) {
      pipeline.set_canvas(canvas);
      uploaded = h;
    }
    device.submit_and_wait([&](VkCommandBuffer cmd) {
      timer.begin_frame(cmd);
      pipeline.record(cmd, &timer);
      hasher.record_all(cmd, {{&b.output, pixels * 16, 0}});
    });
    timer.resolve();
    nlohmann::json record = {{"frame", f}, {"image_hash", hasher.result(0)}};
    image_hashes.push_back(hasher.result(0));
    nlohmann::json ms = nlohmann::json::object();
    for (const gpu::PassTiming& t : timer.timings()) ms[t.name] = t.ms;
    record["pass_ms"] = ms;

    std::optional<Image> output;
    auto read_output = [&]() -> const Image& {
      if (!output) output = pipeline.output();
      return *output;
    };
    FrameData data;
    data.frame = f;
    data.read_output = read_output;
    data.rc_canvas = &canvas;
    data.rc_settings = &settings;
    data.rc_reference = [&]() -> const RcReference& { return references.get(canvas); };
    for (RcCheck& c : checks) {
      if (c.needs.frames && !c.needs.frames->count(f)) continue;
      c.check->observe(FrameView(data, c.needs.reads), record);
    }
    if (captures.count(f) && options.resume_from.empty())
      write_capture(options.out_dir, f, device, pipeline, canvas, hasher.result(0), run_facts);
    if (f + 1 == frames) last = read_output();
    wall_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    log.add(record);
  }
  frames_timed.reset();

  // Each capture keeps the run's frame hashes, for a replay's --verify.
  if (options.resume_from.empty())
    for (std::uint32_t f : captures)
      if (f < frames)
        write_json_file(options.out_dir / capture_folder(f) / "run_hashes.json", {{"frame_images", image_hashes}});

  RunResult result;
  for (RcCheck& c : checks) result.checks.push_back(c.check->result());
  const bool all_pass =
      std::all_of(result.checks.begin(), result.checks.end(), [](const CheckResult& c) { return c.passed(); });
  result.exit_code = all_pass ? 0 : 1;

  // The state after the last frame, hashed on the device.
  const std::vector<std::pair<std::string, gpu::HashRange>> state = {
      {"rc_scene", {&b.scene, pixels * 16, 0}},
      {"rc_distance", {&b.distance, pixels * 4, 0}},
      {"rc_cascade_0", {&b.cascades[pipeline.cascade0_buffer()], pixels * 16, 0}},
      {"rc_mipmap", {&b.mipmap, VkDeviceSize(settings.mip_width()) * settings.mip_height() * 16, 0}},
      {"rc_output", {&b.output, pixels * 16, 0}}};
  std::vector<gpu::HashRange> ranges;
  for (const auto& [_, r] : state) ranges.push_back(r);
  const std::vector<std::string> state_hashes = hasher.hash_now(ranges);
  nlohmann::json final_buffers = nlohmann::json::object();
  for (std::size_t i = 0; i < state.size(); ++i) final_buffers[state[i].first] = state_hashes[i];

  nlohmann::json& s = result.summary;
  s["schema_version"] = 1;
  s["scenario"] = {{"name", scenario.name}, {"file", scenario.file.string()}, {"document", scenario.raw}};
  s["resolved"] = {{"resolution", {settings.width, settings.height}},
                   {"frames", frames},
                   {"seed", seed},
                   {"profile", scenario.profile},
                   {"overrides", scenario.overrides},
                   {"mode", "radiance_cascades"},
                   {"pipeline", "radiance_cascades"},
                   {"profile_values", profile.to_json()},
                   {"radiance_cascades", settings.to_json()},
                   {"backend", gpu::backend_name(device.backend())}};
  s["scene"] = {{"name", "canvas"}, {"shapes", initial.shapes.size()}, {"emitters", initial.emitters()},
                {"canvas", initial.to_json()}};
  s["device"] = device.info().to_json();
  s["build"] = build_info();
  s["verdict"] = all_pass ? "pass" : "fail";
  s["exit_code"] = result.exit_code;
  nlohmann::json check_json = nlohmann::json::array();
  for (const CheckResult& c : result.checks) check_json.push_back(c.to_json());
  s["checks"] = check_json;
  add_frames(log, wall_ms, s);
  s["final_image_hash"] = bytes_hash(last.pixels.data(), last.pixels.size() * sizeof(glm::vec3));
  s["hashes"] = {{"scheme", shader::WORD_HASH_SCHEME},
                 {"first_frame", first_frame},
                 {"frame_images", image_hashes},
                 {"final_buffers", final_buffers}};
  write_exr(options.out_dir / kFinalImageFile, {{"", &last}}, ExrPixels::half);
  s["final_image"] = kFinalImageFile;
  nlohmann::json capture_files = nlohmann::json::array();
  for (std::uint32_t f : captures)
    if (f < frames && options.resume_from.empty()) capture_files.push_back(capture_images_file(f).string());
  s["captures"] = capture_files;
  s["failure_captures"] = nlohmann::json::array();
  if (!options.resume_from.empty())
    s["resumed_from"] = {{"capture", options.resume_from.string()},
                         {"frame", first_frame},
                         {"captured_image_hash", resumed_hash},
                         {"same_bits", !image_hashes.empty() && image_hashes.front() == resumed_hash}};
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  s["wall_seconds"] = wall;
  s["wall_breakdown"] = wall_breakdown(wall, s["frames"], phases_at_start);
  write_json_file(options.out_dir / "summary.json", s);
  spdlog::info("{}: {}", scenario.name, wall_breakdown_line(s["wall_breakdown"]));
  for (const CheckResult& c : result.checks)
    spdlog::log(c.passed() ? spdlog::level::info : spdlog::level::err, "{}: check {} {}: {}", scenario.name, c.name,
                to_string(c.verdict), c.message);
  return result;
}

}  // namespace gi
