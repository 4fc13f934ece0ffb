// Per-signal figures of a realtime run: DI, GI and specular each
// with its per-frame noise (the two chains' difference, summary "noise"),
// its bias against the Embree reference of the same quantity where one
// exists, and its share of the pipeline's ms/frame.
//
// References per signal: DI against Embree's direct-lighting mode (the DI
// the realtime output and core/shared/direct_integrator.h both define); GI
// and specular together ("indirect") against Embree's full image minus its
// DI, halves minus halves, so the difference keeps two independent halves
// and its own noise; specular alone has none (Embree does not split the
// indirect light by the realtime passes' lobes).
//
// ms per signal: the pipeline's passes grouped by the signal they make
// (light tiles and ReSTIR DI; ReSTIR GI and the world cache; specular GI),
// and the shared ones (primary visibility, G-buffer).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/reference/embree_reference.h"

namespace gi {

// The signal a pipeline pass makes: "di", "gi", "specular", "shared", or ""
// for the observation passes.
std::string pass_signal(const std::string& pass);

// {signal: ms} from a summary's "timings" (median ms per pass, summed), for
// one chain (reports/summary.h pass_per_chain: those passes over `chains`).
nlohmann::json signal_ms(const nlohmann::json& timings, std::uint32_t chains);

// Both chains' temporal means of one signal over the window.
struct ChainMeans {
  Image a, b;
};

// Bias of a signal's two-chain temporal mean against a reference of the
// same quantity (compare(): relMSE, noise, bias_relmse, energy ratio).
nlohmann::json signal_bias(const ChainMeans& signal, const Image& ref_mean, const Image& ref_half_a,
                           const Image& ref_half_b);

// Embree's indirect light: full − direct, mean and halves.
ReferenceResult indirect_reference(const ReferenceResult& full, const ReferenceResult& direct);

// The chain figures add up: output noise = Σ signal noises + the mean cross
// term 2·ΣΔiΔj / 2 / (m² + ε) of the chains' differences. With independent
// signal noises the cross term is zero within its standard error (from the
// spread of its 8×8-pixel block means: spatial reuse correlates neighbours).
struct NoiseAdditivity {
  double output = 0, sum_of_signals = 0, cross_term = 0, cross_term_standard_error = 0;
};
NoiseAdditivity chain_noise_additivity(const std::vector<Image>& signals_a, const std::vector<Image>& signals_b,
                                       const Image& denominator_ref);

}  // namespace gi
