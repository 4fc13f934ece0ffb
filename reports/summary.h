// Pieces of summary.json that every command shares: build identity and
// per-pass timing statistics.
#pragma once
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

// The p-quantile (0..1) of v, linearly interpolated; 0 for none.
double percentile(std::vector<double> v, double p);

// The passes that observe the pipeline rather than make its image (the
// output's reductions, the state hash): timed, but left out of the
// pipeline's per-frame total.
inline bool observation_pass(const std::string& name) { return name == "frame_output" || name == "state_hash"; }

// The pipeline's ms/frame from a summary's "timings": the sum of its
// passes' median ms, the observation passes left out (the pipeline a user
// ships does not run them); NaN without timings.
double pipeline_ms_per_frame(const nlohmann::json& timings);

// The passes dispatched once per chain (their z or y dimension): with two
// independent chains (a reference check's noise estimate, `noise: true`)
// they do twice the work a shipped pipeline, which runs one, does.
bool pass_per_chain(const std::string& name);

// The pipeline's ms/frame for one chain: as pipeline_ms_per_frame, with the
// per-chain passes divided by `chains` (the passes every chain shares, such
// as the G-buffer and the world cache, whole). NaN without timings.
double one_chain_ms_per_frame(const nlohmann::json& timings, std::uint32_t chains);

// Per pass: frames, mean, median, p95, min, max (ms), plus the total of the
// means (ms/frame of the recorded passes).
nlohmann::json timing_summary(const std::map<std::string, std::vector<double>>& per_pass_ms);

// giharness version, compiler, build type.
nlohmann::json build_info();

}  // namespace gi
