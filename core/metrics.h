// Image error metrics (docs/design.md §5) and the noise-aware comparison the
// `reference` check uses. Every metric averages over pixels where both images
// are finite; non-finite values are counted separately, never folded in.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"

namespace gi {

// Denominator regulariser of relMSE: mean((x−y)² / (y² + kRelmseEpsilon)).
inline constexpr double kRelmseEpsilon = 0.01;

// relMSE = mean over pixels and channels of (x−y)² / (y² + 0.01).
double relmse(const Image& x, const Image& y);
// mean over pixels and channels of |x−y|.
double mean_abs_error(const Image& x, const Image& y);
// mean over pixels and channels of |x−y| / sqrt(y² + 0.01) (the same
// regularised denominator as relMSE, so mean_rel_error² ≤ relMSE).
double mean_rel_error(const Image& x, const Image& y);
// mean luminance (Rec. 709, as shader::luminance) of x over that of y.
double energy_ratio(const Image& x, const Image& y);
// max pixel luminance of x over max pixel luminance of y (fireflies, clipped
// highlights); 1 when both are 0, +inf when only y is 0.
double max_luminance_ratio(const Image& x, const Image& y);
// Number of non-finite channel values (NaN, ±inf) in x.
std::uint64_t count_nonfinite(const Image& x);
// Mean Rec. 709 luminance over finite pixels.
double mean_luminance(const Image& x);

// Expected relMSE (against the truth, denominator from `denominator_ref`) of
// the mean (a+b)/2 of two independent half-sample images, from the halves'
// difference:  mean((a−b)² / (ref² + 0.01)) / 4.
double estimator_noise(const Image& half_a, const Image& half_b, const Image& denominator_ref);

// Per-frame noise of one chain, from two independent chains a and b of the
// same frame: its expected relMSE against its own expectation,
//   mean((a−b)² / 2 / (ref² + 0.01)) = 2 · estimator_noise(a, b, ref).
double chain_noise(const Image& chain_a, const Image& chain_b, const Image& denominator_ref);

// Standard deviation of mean_luminance((a+b)/2) due to sampling noise,
// treating pixels as independent: sqrt(Σ_p (lum a_p − lum b_p)² / 4) / P.
double mean_luminance_sigma(const Image& half_a, const Image& half_b);

// The p-quantile of Student's t distribution with `dof` degrees of freedom
// (dof ≥ 1; 0 means infinite: the standard normal's). Numerical, deterministic.
double student_t_quantile(double p, std::uint32_t dof);

struct ComparisonVerdict {
  bool passed = false;
  // True when the estimators' own noise is not well below a tolerance being
  // checked and nothing failed beyond noise: the comparison says nothing.
  bool inconclusive = false;
  std::string reason;  // why it failed or was inconclusive; empty on a pass
};

// x (e.g. the GPU image) against y (e.g. the Embree reference), both with
// their independent half-sample images.
struct Comparison {
  // "Well below": the tolerance must be at least this many standard
  // deviations (energy) or noise levels (relMSE) for a verdict to be trusted.
  static constexpr double kNoiseMargin = 3.0;

  double relmse = 0;            // relMSE(x, y)
  double noise_x = 0;           // estimator_noise of x (its expected relMSE against its own limit)
  double noise_y = 0;           // estimator_noise of y
  double combined_noise = 0;    // noise_x + noise_y: relMSE(x, y) expected from noise alone (no bias)
  double relmse_over_noise = 0; // relmse / combined_noise (≈ 1 without bias; +inf if noise is 0 and relmse > 0)
  double bias_relmse = 0;       // max(0, relmse − combined_noise): the part noise does not explain
  double mean_abs_error = 0;
  double mean_rel_error = 0;
  double energy_ratio = 0;       // mean lum(x) / mean lum(y)
  double energy_ratio_sigma = 0; // 1σ of energy_ratio from both images' noise
  // Degrees of freedom of energy_ratio_sigma: 0 when it is summed over
  // pixels taken as independent (many), K − 1 when it comes from the spread of
  // K independent chains' image means (compare_chains). The energy verdict's
  // margin is the t quantile of the same false-alarm rate as kNoiseMargin σ
  // of a normal (two-sided 0.27 %).
  std::uint32_t energy_dof = 0;
  double max_luminance_ratio = 0;
  std::uint64_t nonfinite_x = 0, nonfinite_y = 0;  // in the mean images

  // Verdict, in this order (relmse_tolerance ≤ 0: no absolute relMSE limit,
  // i.e. x must match y within noise):
  // - fail when any mean value is non-finite; when relmse > noise_factor ×
  //   combined_noise + relmse_tolerance (x and y differ by more than noise
  //   and the allowed bias explain); or when |energy_ratio − 1| >
  //   energy_tolerance + kNoiseMargin × energy_ratio_sigma (an energy error
  //   that noise cannot explain);
  // - else inconclusive when the noise is not well below a tolerance being
  //   checked: kNoiseMargin × energy_ratio_sigma > energy_tolerance, or
  //   kNoiseMargin × combined_noise > relmse_tolerance (if one is given);
  // - else pass when |energy_ratio − 1| ≤ energy_tolerance.
  ComparisonVerdict judge(double noise_factor, double energy_tolerance, double relmse_tolerance = 0) const;
  bool passes(double noise_factor, double energy_tolerance) const { return judge(noise_factor, energy_tolerance).passed; }
  bool inconclusive(double noise_factor, double energy_tolerance) const {
    return judge(noise_factor, energy_tolerance).inconclusive;
  }
  // The margin, in σ, with the tail probability of kNoiseMargin σ of a
  // normal (0.135 % one-sided, 0.27 % two-sided) for a σ estimated with
  // `dof` degrees of freedom: Student's t quantile (0: kNoiseMargin itself).
  static double noise_margin(std::uint32_t dof);
};

// x given as K ≥ 2 independent chains' images (x = their mean): x's noise
// per pixel from the chains' sample variance / K (for K = 2 it is
// estimator_noise), and its energy σ from the spread of the chains' mean
// luminances / √K, with K − 1 degrees of freedom: a chain's error that is
// shared by all its pixels (a world cache's cell placement, a light tile) is
// in it, where a sum over pixels taken as independent misses it.
Comparison compare_chains(const std::vector<Image>& chains, const Image& y_mean, const Image& y_half_a,
                          const Image& y_half_b);

// Sizes must match (throws std::invalid_argument otherwise).
Comparison compare(const Image& x_mean, const Image& x_half_a, const Image& x_half_b, const Image& y_mean,
                   const Image& y_half_a, const Image& y_half_b);

}  // namespace gi
