#include "replay/run_setup.h"

#include <algorithm>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/errors.h"
#include "core/scene_builder.h"
#include "core/scene_flatten.h"
#include "checks/check_registry.h"
#include "gpu/realtime_settings.h"

namespace gi {
namespace {

// The scenario's own captures past a shortened run (--frames) are skipped
// with a note (schema.json: "frames past the run are never reached"); a
// --capture past it is a mistake on the command line.
void plan_captures(const Scenario& scenario, const RunOptions& options, RunSetup& s) {
  for (std::uint32_t f : scenario.capture) {
    if (f < s.frames) {
      s.captures.insert(f);
      continue;
    }
    s.skipped_captures.push_back(f);
    spdlog::warn("{}: capture at frame {} skipped: the run has {} frames (--frames)", scenario.name, f, s.frames);
  }
  for (std::uint32_t f : options.capture) {
    if (f >= s.frames)
      throw InputError("--capture", "", fmt::format("frame {} is past the run's last frame {}", f, s.frames - 1));
    s.captures.insert(f);
  }
}

}  // namespace

RunSetup::RunSetup(const Scenario& scenario, const RunOptions& options)
    : frames(options.frames.value_or(scenario.frames)),
      seed(options.seed.value_or(scenario.seed)),
      width(scenario.resolution[0]),
      height(scenario.resolution[1]),
      realtime(scenario.mode == RenderMode::Realtime),
      profile(resolve_profile(scenario, options.profile, options.sets)),
      settings(realtime_settings(profile)),
      initial(build_scene(scenario)),
      geometry(flatten_geometry(initial)) {
  if (frames == 0) throw InputError("--frames", "", "expected a frame count of at least 1");
  if (scenario.gi && !realtime)
    throw InputError(scenario.file.string(), "/gi", "\"gi\": true in \"mode\": \"realtime\" only");
  if (scenario.cache_view && !realtime)
    throw InputError(scenario.file.string(), "/cache_view", "\"cache_view\": true in \"mode\": \"realtime\" only");
  for (const std::string& w : initial.warnings) spdlog::warn("{}: {}", scenario.name, w);
  apply_material_model(initial, settings);  // materials only: the geometry above stays
  gi = realtime && scenario.gi;
  // Without the debug view only GI's queries put cells in the cache.
  cache_fed = scenario.cache_view || (gi && settings.gi.queries_world_cache());
  plan_captures(scenario, options, *this);

  for (const CheckSpec& spec : scenario.checks) {
    const CheckContext context{scenario, spec,     profile, options,   initial, frames,
                               seed,     realtime, gi,      cache_fed, &settings};
    checks.push_back(make_check(context));
    needs.push_back(checks.back()->needs());
  }
  std::uint32_t wanted_chains = scenario.noise ? 2u : 1u;
  bool gbuffer = false, root_frame = false, temporal_edges = false,
       path_counters = false;
  for (const CheckNeeds& n : needs) {
    captures.insert(n.captures.begin(), n.captures.end());
    record_hashes = record_hashes || n.record_hashes;
    gbuffer = gbuffer || n.gbuffer;
    wanted_chains = std::max(wanted_chains, n.chains);
    root_frame = root_frame || n.cache_root_frame;
    temporal_edges = temporal_edges || n.gi_temporal_edges;
    path_counters = path_counters || n.gi_path_counters;
    warmup_frames = std::max(warmup_frames, n.warmup_frames);
  }
  // Captures carry the run's hashes (replay --verify), replays record theirs.
  const bool hashes_wanted = record_hashes || options.record_hashes || !options.resume_from.empty();
  record_hashes = hashes_wanted || !captures.empty();
  hash_log_from = hashes_wanted || captures.empty() ? 0u : *captures.begin();

  gpu::RendererOptions& r = renderer_options;
  r.width = width;
  r.height = height;
  // Only what this scenario uses; runs that record hashes (captures, replays,
  // the determinism check) always list the same buffers, G-buffer included.
  r.gbuffer = realtime || gbuffer || !captures.empty() || record_hashes;
  r.reference = !realtime;
  r.reference_options.background = initial.background;
  r.frame_output = true;
  // One chain per pipeline: the second chain is a pipeline of its own.
  chains = realtime ? wanted_chains : 1u;
  const std::uint32_t chains_per_pipeline = 1u;
  if (realtime) {
    // Specular GI beside DI takes the smoothest surfaces' specular lobe from it.
    fit_to_run(settings, flatten_instances(initial, geometry), gi && settings.gi.specular, chains_per_pipeline);
    settings.di.background = initial.background;
    r.di = settings.di;
    r.normal_map_decode = settings.normal_map_decode;
    r.motion_vectors = settings.motion_vectors;
  }
  if (gi) {
    settings.gi.temporal_edge_stats = temporal_edges;  // compiled in only for a check that reads it
    settings.gi.path_counters = path_counters;
    r.gi = settings.gi;
  }
  if (cache_fed) {
    settings.cache.view = scenario.cache_view;
    settings.cache.stats = true;
    settings.cache.root_frame = root_frame;  // instrumentation compiled in only for a check that reads it
    r.world_cache = settings.cache;
  }
}

std::uint32_t independent_chain_seed(std::uint32_t seed, std::uint32_t chain) {
  // splitmix64's finaliser over the seed, the chain and a salt of this rule's own ("CH").
  std::uint64_t z = (std::uint64_t(seed) << 32 | (0x4348u << 16) | (chain & 0xFFFFu)) + 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return std::uint32_t(z ^ (z >> 32));
}

}  // namespace gi
