// The first part of a run (replay/run_scenario.h): everything decided before
// a device exists. The scenario's profile and initial scene, the frames to
// capture, the checks (made through their registry, each parsing its own
// parameters), and the renderer's options: only the passes and buffers the
// scenario and its checks use.
#pragma once
#include <cstdint>
#include <memory>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/profile.h"
#include "core/scenario.h"
#include "core/scene.h"
#include "core/scene_flatten.h"
#include "gpu/realtime_settings.h"
#include "gpu/renderer.h"
#include "checks/check.h"
#include "replay/run_scenario.h"

namespace gi {

struct RunSetup {
  // InputError (exit 2) for a scenario or an option the run cannot honour.
  RunSetup(const Scenario& scenario, const RunOptions& options);
  RunSetup(const RunSetup&) = delete;  // the checks hold references into it
  RunSetup& operator=(const RunSetup&) = delete;

  std::uint32_t frames = 0, seed = 0, width = 0, height = 0;
  bool realtime = false;   // "mode": "realtime"
  bool gi = false;         // ReSTIR GI and specular GI run
  bool cache_fed = false;  // the world cache runs
  Profile profile;
  // Every profile key, resolved once through the profile table
  // (gpu/profile_keys.cpp) and fitted to this run (the scene's light tiles,
  // the handover to specular GI, one chain per pipeline): renderer_options
  // and the checks (CheckContext::settings) take their parts from here.
  RealtimeSettings settings;
  Scene initial;
  FlatGeometry geometry;  // the initial scene's, flattened once (the frame loop takes it)
  std::set<std::uint32_t> captures;  // the scenario's, --capture's and the checks'
  nlohmann::json skipped_captures = nlohmann::json::array();  // the scenario's, past a --frames run
  bool record_hashes = false;
  // The hash log's first frame: 0, or a run that logs only for its captures
  // logs from its first capture on (a replay of a capture compares the frames
  // from the capture's on; hashing each earlier frame would be the GPU's time
  // for no reader).
  std::uint32_t hash_log_from = 0;
  // Realtime chains for the checks' noise estimates (the most any check asks
  // for; 2 with "noise"): chain A is the run's pipeline, each other chain a
  // pipeline of its own at independent_chain_seed(seed, chain), so the chains
  // share nothing (not the world cache, not the light tiles, not a
  // permutation) and their spread sees every source of variance the seed brings.
  std::uint32_t chains = 1;
  gpu::RendererOptions renderer_options;  // one chain's pipeline
  // In the scenario's order; needs[i] is checks[i]'s declaration.
  std::vector<std::unique_ptr<Check>> checks;
  std::vector<CheckNeeds> needs;
  std::uint32_t warmup_frames = 0;  // the largest any check asks for
};

// Chain k's seed (k ≥ 1; chain 0 runs at the run's seed): a mix of the run's
// seed and k with a constant of this rule's own, so it is not the seed another
// run of the scenario would use (seed sets derive theirs with another rule).
std::uint32_t independent_chain_seed(std::uint32_t seed, std::uint32_t chain);

}  // namespace gi
