// Every shader variant a released profile makes a run compile, compiled to
// SPIR-V with glslang. Shaders are compiled only at run time, each pass with
// the defines its settings give (gpu/shader_compiler.h), so a syntax error
// under an #if that only one profile switch or one scenario's check selects
// would otherwise surface only when a run picks it (audit 2026-12-05 §7).
//
// The variants: each scenario of the default suite (scenarios/*.json) under
// each released profile of its pipeline (scenarios/profiles/*.json), and
// each bug-museum and expected-failure scenario under its own profile, set up
// as a run sets them up (replay/run_setup.h: the profile, the scenario's
// overrides, its checks' instrumentation), then listed pass by pass as
// gpu::Renderer builds them, for each tracing backend's defines; plus the
// equal-time GPU path tracer's reference pass, the radiance-cascades passes
// and `giharness bench`'s ray-list tracer. Deduplicated, then compiled.
//
// No device is needed: a pipeline is created only on the device (lavapipe's
// slow part). The SPIR-V cache (cache_root()/spirv) is shared with the runs;
// a hit needs the same compiler version, defines and resolved source (every
// include's content), so only a variant that compiled before is skipped.
//
// The list is this file's reading of gpu/renderer.cpp and the passes: there
// is no device-free list in the code (the prewarm sees pipelines only as a
// device creates them, as SPIR-V). ShaderVariantsOnDevice holds the reading
// to the Renderer: on the device, the cache keys a Renderer compiles are
// exactly the keys of the variants listed here for the same options.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include "core/data_dir.h"
#include "core/errors.h"
#include "core/profile.h"
#include "core/scenario.h"
#include "gpu/bvh_buffers.h"
#include "gpu/device.h"
#include "gpu/passes/buffer_hash.h"
#include "gpu/passes/frame_output.h"
#include "gpu/passes/gbuffer_resolve.h"
#include "gpu/passes/light_tiles.h"
#include "gpu/passes/primary_visibility.h"
#include "gpu/passes/ray_list_trace.h"
#include "gpu/passes/reference_path_trace.h"
#include "gpu/passes/restir_di.h"
#include "gpu/passes/restir_gi.h"
#include "gpu/passes/specular_gi.h"
#include "gpu/passes/timing_calibration.h"
#include "gpu/profile_keys.h"
#include "gpu/rc/rc_passes.h"
#include "gpu/rc/rc_pipeline.h"
#include "gpu/renderer.h"
#include "gpu/shader_compiler.h"
#include "replay/run_setup.h"
#include "tests/test_support.h"

namespace gi {
namespace {

namespace fs = std::filesystem;
using gpu::ShaderDefine;
using Defines = std::vector<ShaderDefine>;

struct Variant {
  std::string file;  // relative to the data folder
  Defines globals;   // the compiler's global defines (ShaderCompiler::set_global_defines)
  Defines defines;   // the pass's own
};

std::string defines_text(const Defines& d) {
  std::string s;
  for (const ShaderDefine& x : d) s += (s.empty() ? "" : ", ") + (x.value.empty() ? x.name : x.name + "=" + x.value);
  return s.empty() ? "(none)" : s;
}

std::string describe(const Variant& v) {
  return fmt::format("{} [global: {}; own: {}]", v.file, defines_text(v.globals), defines_text(v.defines));
}

// ---- The list: what gpu::Renderer(options) compiles (gpu/renderer.cpp's
// constructor and the constructors of the passes it builds), in its order.
// `backend`: gpu::trace_backend_defines of the device.

Defines reference_defines(const gpu::ReferencePathTraceOptions& o) {  // gpu/passes/reference_path_trace.cpp
  Defines d = {{"REFERENCE_MAX_BOUNCES", std::to_string(o.max_bounces) + "u"}};
  if (o.background != glm::vec3(0.0f))
    d.push_back({"REFERENCE_BACKGROUND",
                 fmt::format("vec3({:.9g},{:.9g},{:.9g})", o.background.x, o.background.y, o.background.z)});
  if (o.direct_only) d.push_back({"REFERENCE_DIRECT_ONLY", "1"});
  return d;
}

std::vector<Variant> renderer_variants(const gpu::RendererOptions& o, const Defines& backend) {
  Defines globals = backend;
  globals.push_back({"NORMAL_MAP_DECODE", std::to_string(o.normal_map_decode)});
  std::vector<Variant> out;
  auto add = [&](const std::string& file, Defines own = {}) { out.push_back({file, globals, std::move(own)}); };
  if (o.timing_calibration) add(gpu::TimingCalibration::kShader);
  if (o.gbuffer) {
    add(gpu::PrimaryVisibility::kShader);
    Defines motion;
    if (o.motion_vectors == gpu::MotionVectors::object) motion.push_back({"GBUFFER_MOTION_OBJECT", ""});
    if (o.motion_vectors == gpu::MotionVectors::ignored) motion.push_back({"GBUFFER_MOTION_IGNORED", ""});
    add(gpu::GBufferResolve::kShader, motion);
  }
  if (o.reference) add(gpu::ReferencePathTrace::kShader, reference_defines(o.reference_options));
  if (o.di)  // gpu/passes/di_pipeline.cpp
    for (const char* f : {gpu::LightTiles::kShader, gpu::DiInitialTemporal::kShader, gpu::DiSpatialShade::kShader})
      add(f, o.di->defines());
  const bool gi_queries_cache = o.gi && o.gi->queries_world_cache();
  Defines cache_defines;
  if (o.world_cache) {  // the settings as the Renderer completes them, then gpu/passes/world_cache.cpp
    gpu::WorldCacheSettings cache = *o.world_cache;
    if (gi_queries_cache) {
      const std::uint32_t extra = o.gi->initial_samples - 1u;
      cache.external_queries_per_pixel = o.gi->chains * (extra > 0 ? 2u + extra : (o.gi->specular ? 2u : 1u));
    }
    if (cache.tile_candidates && o.di) {
      cache.tile_count = o.di->tile_count;
      cache.tile_samples = o.di->samples_per_tile;
    }
    const std::uint32_t pending = std::max(o.width * o.height * (1u + cache.external_queries_per_pixel), cache.cells);
    cache_defines = cache.defines(pending);
    for (const char* name : {"world_cache_decay", "world_cache_compact_scan",
                             "world_cache_compact_write", "world_cache_sample_di", "world_cache_sample_gi",
                             "world_cache_pending_args", "world_cache_commit", "world_cache_blend", "world_cache_stats"})
      add(fmt::format("gpu/shaders/{}.comp", name), cache_defines);
    if (cache.view) add("gpu/shaders/world_cache_query_pixels.comp", cache_defines);
  }
  if (o.gi) {  // gpu/passes/gi_pipeline.cpp
    gpu::GiSettings gi = *o.gi;
    if (gi_queries_cache) gi.world_cache_defines = cache_defines;
    add(gpu::GiInitialTemporal::kShader, gi.defines());
    add(gpu::GiSpatialShade::kShader, gi.defines());
    if (gi.specular) add(gpu::SpecularGi::kShader, gi.defines());
  }
  if (o.frame_output) {  // gpu/passes/frame_output.cpp: the pass, its reduction, its hash
    add(gpu::FrameOutput::kShader);
    add(gpu::FrameOutput::kShader, {{"FRAME_OUTPUT_REDUCE", ""}});
    add(gpu::BufferHash::kShader);
  }
  return out;
}

// The radiance-cascades pipeline (gpu/rc/rc_pipeline.cpp) and the run's
// hasher (replay/rc_run.cpp): a compiler of their own, no defines.
std::vector<Variant> rc_variants(const RcSettings& s) {
  std::vector<Variant> out;
  for (const char* f : {gpu::RcScene::kShader, gpu::RcCascade::kShader, gpu::RcMipmap::kShader, gpu::RcApply::kShader})
    out.push_back({f, {}, {}});
  if (s.jfa) {
    out.push_back({gpu::JfaSeed::kShader, {}, {}});
    out.push_back({gpu::JfaStep::kShader, {}, {}});
  } else {
    out.push_back({gpu::RcDistance::kShader, {}, {}});
  }
  out.push_back({gpu::BufferHash::kShader, {}, {}});
  return out;
}

// The tracing backends' variants (gpu/bvh_buffers.cpp, trace_backend_defines):
// rayquery; bvh on a CPU device (lavapipe); bvh on a GPU (H100/H200).
const std::vector<std::pair<std::string, Defines>>& backends() {
  static const std::vector<std::pair<std::string, Defines>> b = {
      {"rayquery", {}},
      {"bvh on a CPU device", {{"TRACE_BACKEND_BVH", ""}, {"BVH_TRAVERSAL_ONE_LOOP", ""}}},
      {"bvh on a GPU", {{"TRACE_BACKEND_BVH", ""}}}};
  return b;
}

// Everything one (profile, scenario) run may compile, on any backend:
// the run's pipeline (its other chains are the same), on a CPU device with
// the timing calibration kernel, with and without the cache view; the equal-time GPU path tracer
// (replay/equal_time.cpp: the reference pass alone, with or without
// direct_only); the RC pipeline for a canvas scenario.
std::vector<Variant> run_variants(const Scenario& scenario, const std::string& profile) {
  RunOptions options;
  options.profile = profile;
  options.quiet = true;
  if (scenario.pipeline == Pipeline::RadianceCascades) {
    const Profile p = resolve_profile(scenario, profile, {});
    if (!profile_has_family(p, ProfileFamily::radiance_cascades))
      throw InputError("--profile", "", "not a radiance-cascades profile");
    return rc_variants(rc_settings(p, scenario.canvas->width, scenario.canvas->height));
  }
  const RunSetup setup(scenario, options);
  // The world cache's debug view (a scenario's "cache_view": true) on any
  // realtime scenario: its query pass, and the cache where GI does not feed one.
  std::optional<RunSetup> viewed;
  if (setup.realtime && !scenario.cache_view) {
    Scenario with_view = scenario;
    with_view.cache_view = true;
    viewed.emplace(with_view, options);
  }
  std::vector<Variant> out;
  for (const auto& [name, backend] : backends()) {
    for (const RunSetup* s : {&setup, viewed ? static_cast<const RunSetup*>(&*viewed) : nullptr}) {
      if (!s) continue;
      gpu::RendererOptions r = s->renderer_options;
      r.timing_calibration = true;
      for (Variant& v : renderer_variants(r, backend)) out.push_back(std::move(v));
    }
    if (setup.realtime)
      for (bool direct_only : {false, true}) {
        gpu::RendererOptions peer;
        peer.width = setup.width;
        peer.height = setup.height;
        peer.gbuffer = false;
        peer.reference = true;
        peer.reference_options.background = setup.initial.background;
        peer.reference_options.direct_only = direct_only;
        for (Variant& v : renderer_variants(peer, backend)) out.push_back(std::move(v));
      }
  }
  return out;
}

std::vector<fs::path> json_files(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json" && e.path().filename() != "schema.json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Quiet while runs are set up: the scenarios' own warnings are not the point here.
struct QuietLog {
  spdlog::level::level_enum was = spdlog::get_level();
  QuietLog() { spdlog::set_level(spdlog::level::off); }
  ~QuietLog() { spdlog::set_level(was); }
};

TEST(ShaderVariants, EveryVariantTheReleasedProfilesUseCompilesWithGlslang) {
  const QuietLog quiet;
  const fs::path scenarios = test::source_dir() / "scenarios";
  std::vector<std::string> profiles;
  for (const fs::path& f : json_files(scenarios / "profiles")) profiles.push_back(f.stem().string());
  ASSERT_GE(profiles.size(), 4u) << "solari-0.17, 0.18, 0.19 and radiance-cascades-lesson at least";

  // (scenario file, profile) pairs: the default suite under every profile,
  // the museum and the expected failures under their own.
  std::vector<std::pair<fs::path, std::string>> pairs;
  for (const fs::path& f : json_files(scenarios))
    for (const std::string& p : profiles) pairs.emplace_back(f, p);
  for (const char* dir : {"bugs", "expected_failures"})
    for (const fs::path& f : json_files(scenarios / dir)) pairs.emplace_back(f, "");

  std::map<std::string, Variant> variants;            // by describe()
  std::map<std::string, std::string> first_user;      // variant -> the first pair that compiles it
  std::map<std::string, std::size_t> users;
  std::size_t set_up = 0;
  std::vector<std::string> not_valid;  // pairs a run refuses (a Solari profile on a canvas, ...)
  for (const auto& [file, profile] : pairs) {
    const Scenario scenario = load_scenario(file);
    const std::string own = profile.empty() ? scenario.profile : profile;
    const std::string label = fs::relative(file, scenarios).string() + " under " + own;
    std::vector<Variant> list;
    try {
      list = run_variants(scenario, own);
    } catch (const std::exception& e) {
      // Only another profile than the scenario's own may be refused.
      EXPECT_NE(own, scenario.profile) << label << ": its own profile is refused: " << e.what();
      not_valid.push_back(label);
      continue;
    }
    ++set_up;
    for (Variant& v : list) {
      const std::string d = describe(v);
      if (users[d]++ == 0) first_user[d] = label;
      variants.emplace(d, std::move(v));
    }
  }
  // `giharness bench`'s ray-list tracer: no defines of its own.
  for (const auto& [name, backend] : backends())
    variants.emplace(describe({gpu::RayListTrace::kShader, backend, {}}), Variant{gpu::RayListTrace::kShader, backend, {}});
  EXPECT_GT(set_up, pairs.size() / 2) << "most pairs must set up; refused: " << not_valid.size();

  // One compiler per core, each taking the next variant: with an empty
  // SPIR-V cache the compiles are most of this test's time (glslang keeps no
  // state between TShaders, and the cache's files are renamed into place).
  std::set<std::string> listed_files;
  std::vector<const std::pair<const std::string, Variant>*> todo;
  for (const auto& entry : variants) {
    listed_files.insert(fs::path(entry.second.file).filename().string());
    todo.push_back(&entry);
  }
  std::vector<std::string> failures;
  std::mutex failures_mutex;
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    gpu::ShaderCompiler compiler;
    for (std::size_t i = next++; i < todo.size(); i = next++) {
      const auto& [d, v] = *todo[i];
      compiler.set_global_defines(v.globals);
      try {
        compiler.compile_file(v.file, v.defines);
      } catch (const std::exception& e) {
        const std::lock_guard lock(failures_mutex);
        failures.push_back(fmt::format("{}\n  used by {} pairs, first {}\n{}", d, users.at(d), first_user.at(d), e.what()));
      }
    }
  };
  std::vector<std::thread> workers;
  for (unsigned t = 1; t < std::max(1u, std::thread::hardware_concurrency()); ++t) workers.emplace_back(work);
  work();
  for (std::thread& t : workers) t.join();
  std::sort(failures.begin(), failures.end());
  EXPECT_TRUE(failures.empty()) << failures.size() << " of " << variants.size()
                                << " shader variants do not compile:\n\n"
                                << fmt::format("{}", fmt::join(failures, "\n\n"));

  // Every compute shader is some variant's: a new .comp must join the list above.
  for (const auto& e : fs::directory_iterator(data_dir() / "gpu/shaders"))
    if (e.path().extension() == ".comp") {
      EXPECT_TRUE(listed_files.count(e.path().filename().string()))
          << e.path().filename().string() << " is compiled by no variant listed here (tests/shader_variants_test.cpp)";
    }
}

// ---- The list held to the Renderer, on the device: each Renderer compiles
// into a cache folder of its own, whose files are named by the cache keys
// (gpu/shader_compiler.h); the variants listed for the same options and the
// device's backend compile to exactly those keys. One device for all, so
// that a pipeline the configurations share is created once.

std::set<std::string> spirv_keys(const fs::path& cache) {
  std::set<std::string> keys;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(cache / "spirv", ec))
    if (e.path().extension() == ".spv") keys.insert(e.path().stem().string());
  return keys;
}

std::set<std::string> listed_keys(const std::vector<Variant>& list, const fs::path& cache) {
  gpu::ShaderCompiler compiler(cache);
  std::set<std::string> keys;
  for (const Variant& v : list) {
    compiler.set_global_defines(v.globals);
    keys.insert(fmt::format("{:016x}", compiler.compile_file(v.file, v.defines).key));
  }
  return keys;
}

TEST(ShaderVariantsOnDevice, TheListedVariantsAreWhatTheRendererCompiles) {
  const QuietLog quiet;
  gpu::Device device(std::nullopt, test::test_backend());
  const Defines backend = gpu::trace_backend_defines(device);
  test::TempDir dir("shader-variants");
  int n = 0;
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"cornell_box.json", "solari-0.18"},  // reference mode
      {"di_cornell_box.json", "solari-0.17"},
      {"di_moving_occluder.json", "solari-0.19"},
      {"gi_cornell_box.json", "solari-0.17"},
      {"gi_cornell_box.json", "solari-0.18"},
      {"gi_cornell_box.json", "solari-0.19"},
      {"cache_light_toggle_closed_room.json", "solari-0.18"},  // cache_lifetime: the root-frame instrumentation
      {"gi_edge_reuse_cornell.json", "solari-0.18"},           // temporal_acceptance: GI's temporal edge statistics
      {"specular_ray_budget_mirror.json", "solari-0.19"},      // ray_budget: GI's path counters
      {"rc_lamp_and_wall.json", "radiance-cascades-lesson"},
      {"rc_lamp_and_wall_jfa.json", "radiance-cascades-lesson"}};
  for (const auto& [name, profile] : pairs) {
    const fs::path file = test::source_dir() / "scenarios" / name;
    const Scenario scenario = load_scenario(file);
    const std::string label = fmt::format("{} under {}", name, profile);
    const fs::path cache = dir.path() / std::to_string(n++);
    std::vector<Variant> list;
    if (scenario.pipeline == Pipeline::RadianceCascades) {
      const RcSettings s = rc_settings(resolve_profile(scenario, profile, {}), scenario.canvas->width,
                                       scenario.canvas->height);
      {
        gpu::ShaderCompiler compiler(cache);
        gpu::RcPipeline pipeline(device, compiler, s);
        gpu::BufferHash hasher(device, compiler, 1);
      }
      list = rc_variants(s);
    } else {
      RunOptions options;
      options.profile = profile;
      RunSetup setup(scenario, options);
      setup.renderer_options.timing_calibration = device.info().device_type == "cpu";  // as the frame loop sets it
      {
        gpu::ShaderCompiler compiler(cache);
        gpu::Renderer renderer(device, compiler, setup.geometry, setup.renderer_options);
      }
      list = renderer_variants(setup.renderer_options, backend);
    }
    const std::set<std::string> compiled = spirv_keys(cache);
    ASSERT_FALSE(compiled.empty()) << label;
    EXPECT_EQ(listed_keys(list, cache), compiled)
        << label << ": the variants listed in tests/shader_variants_test.cpp are not the ones gpu::Renderer compiles";
  }
  EXPECT_EQ(n, int(pairs.size()));
}

}  // namespace
}  // namespace gi
