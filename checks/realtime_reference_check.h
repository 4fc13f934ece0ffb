// The `reference` check for the realtime mode (docs/design.md §5, §6): the realtime
// output against Embree: DI alone against the direct-lighting reference
// (core/shared/direct_integrator.h defines "DI" for both), or with "gi": true
// DI + GI + specular against the full path tracer, per compared frame and for the temporal mean over the
// static window that frame ends.
//
// Noise honesty: temporal reuse correlates a chain's frames, so halves made of
// even and odd frames would understate the noise. The run renders K ≥ 2
// independent chains instead, each a pipeline of its own (own light tiles,
// reservoirs, world cache, random streams); their temporal means are K
// independent estimates, and their spread estimates the noise of their
// average (metrics.h compare_chains). Chains inside one pipeline shared its
// world cache, whose cell placement freezes a seed-dependent error for the
// whole run: that error was in neither chain's difference (README "Error
// bars"). The per-frame figures are for chain A alone, whose noise is twice
// that of a two-chain average (Var(A) = E[(A − B)²] / 2).
//
// Statistical model of the verdict (metrics.h Comparison::judge): relMSE of
// the chains' mean against the reference ≤ relmse_noise_factor × (its
// expected value from noise) + relmse_tolerance (the pipeline's known bias);
// |energy ratio − 1| ≤ energy_tolerance + q σ, q the quantile of a two-sided
// 0.27 % false-alarm rate (3 for a σ summed over pixels, Student's t with
// K − 1 degrees of freedom for a σ from K ≥ 3 chains).
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "core/image.h"
#include "core/metrics.h"
#include "core/scene.h"
#include "checks/check_result.h"
#include "checks/reference_check.h"

namespace gi {

// What the pipeline hands the check at a compared frame.
struct RealtimeEstimate {
  std::vector<Image> frames;  // this frame's image of each chain (2 or more)
  std::vector<Image> means;   // each chain's temporal mean over the window
  std::uint32_t window_start = 0, window_frames = 0;
  // The images are DI + GI + specular ("gi": true): compared with the Embree
  // full path tracer instead of its direct-lighting mode.
  bool full_gi = false;
};

// Error on pixels near strong luminance edges of the reference (shadow
// boundaries, penumbrae — where "halo" shadows sit): relMSE over pixels whose
// 7×7 neighbourhood in the reference spans a luminance ratio above 2.
double edge_region_relmse(const Image& x, const Image& reference);

// The mean of chains' images, pixel by pixel.
Image chain_average(const std::vector<Image>& chains);
inline Image chain_average(const Image& a, const Image& b) { return chain_average(std::vector<Image>{a, b}); }

class RealtimeReferenceCheck : public ReferenceComparisons {
 public:
  using ReferenceComparisons::ReferenceComparisons;
  void compare_frame(std::uint32_t frame, const Scene& scene, const RealtimeEstimate& gpu);
  CheckResult result() const;

 private:
  struct FrameComparison {
    std::uint32_t frame, window_start, window_frames;
    Comparison temporal;   // (A + B)/2 of the temporal means
    Comparison per_frame;  // chain A's frame, noise scaled to one chain
    ComparisonVerdict verdict;
    double temporal_edge_relmse, reference_seconds;
    bool reference_cached, full_gi;
    std::string evidence;
    std::uint32_t chains;
    // The energy ratio's 1σ from the chains' spread (K − 1 degrees of
    // freedom), whichever σ the verdict used.
    double energy_ratio_sigma_chains;
  };
  std::vector<FrameComparison> frames_;
};

}  // namespace gi
