#include "core/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/shared/host_device.h"

namespace gi {
namespace {

void require_same_size(const Image& a, const Image& b, const char* what) {
  if (a.width != b.width || a.height != b.height || a.size() != b.size())
    throw std::invalid_argument(std::string(what) + ": images differ in size");
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double lum(const glm::vec3& c) { return double(shader::luminance(c)); }

// Mean over pixels and channels of term(x, y) where both pixels are finite.
// Pixel sums run in pixel order in double: deterministic.
template <class F>
double mean_channels(const Image& x, const Image& y, const char* what, F term) {
  require_same_size(x, y, what);
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const glm::vec3& a = x.pixels[i];
    const glm::vec3& b = y.pixels[i];
    if (!finite3(a) || !finite3(b)) continue;
    for (int c = 0; c < 3; ++c) sum += term(double(a[c]), double(b[c]));
    n += 3;
  }
  return n ? sum / double(n) : 0.0;
}

}  // namespace

double relmse(const Image& x, const Image& y) {
  return mean_channels(x, y, "relmse", [](double a, double b) { return (a - b) * (a - b) / (b * b + kRelmseEpsilon); });
}

double mean_abs_error(const Image& x, const Image& y) {
  return mean_channels(x, y, "mean_abs_error", [](double a, double b) { return std::abs(a - b); });
}

double mean_rel_error(const Image& x, const Image& y) {
  return mean_channels(x, y, "mean_rel_error",
                       [](double a, double b) { return std::abs(a - b) / std::sqrt(b * b + kRelmseEpsilon); });
}

double mean_luminance(const Image& x) {
  double sum = 0;
  std::size_t n = 0;
  for (const glm::vec3& p : x.pixels)
    if (finite3(p)) sum += lum(p), ++n;
  return n ? sum / double(n) : 0.0;
}

double energy_ratio(const Image& x, const Image& y) {
  require_same_size(x, y, "energy_ratio");
  const double lx = mean_luminance(x), ly = mean_luminance(y);
  if (ly == 0.0) return lx == 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
  return lx / ly;
}

double max_luminance_ratio(const Image& x, const Image& y) {
  require_same_size(x, y, "max_luminance_ratio");
  double mx = 0, my = 0;
  for (const glm::vec3& p : x.pixels)
    if (finite3(p)) mx = std::max(mx, lum(p));
  for (const glm::vec3& p : y.pixels)
    if (finite3(p)) my = std::max(my, lum(p));
  if (my == 0.0) return mx == 0.0 ? 1.0 : std::numeric_limits<double>::infinity();
  return mx / my;
}

std::uint64_t count_nonfinite(const Image& x) {
  std::uint64_t n = 0;
  for (const glm::vec3& p : x.pixels)
    for (int c = 0; c < 3; ++c) n += std::isfinite(p[c]) ? 0 : 1;
  return n;
}

// Why /4: let each pixel's samples have variance σ² and the full estimate be
// the mean m of N samples, so Var(m) = σ²/N — that is the expected squared
// error of m against the truth (no bias). The halves a and b are independent
// means of N/2 samples each: Var(a) = Var(b) = 2σ²/N, hence
// E[(a−b)²] = Var(a) + Var(b) = 4σ²/N = 4 Var(m). So (a−b)²/4 is an unbiased
// estimate of m's squared error, and dividing by (ref² + 0.01) as relMSE does
// gives m's expected relMSE. (With an odd sample count the halves differ by
// one sample; the estimate is then off by O(1/N).)
double estimator_noise(const Image& half_a, const Image& half_b, const Image& denominator_ref) {
  require_same_size(half_a, half_b, "estimator_noise");
  require_same_size(half_a, denominator_ref, "estimator_noise");
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < half_a.size(); ++i) {
    const glm::vec3 &a = half_a.pixels[i], &b = half_b.pixels[i], &r = denominator_ref.pixels[i];
    if (!finite3(a) || !finite3(b) || !finite3(r)) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = double(a[c]) - double(b[c]);
      sum += d * d / (double(r[c]) * double(r[c]) + kRelmseEpsilon);
    }
    n += 3;
  }
  return n ? sum / double(n) / 4.0 : 0.0;
}

double chain_noise(const Image& chain_a, const Image& chain_b, const Image& denominator_ref) {
  return 2.0 * estimator_noise(chain_a, chain_b, denominator_ref);
}

double mean_luminance_sigma(const Image& half_a, const Image& half_b) {
  require_same_size(half_a, half_b, "mean_luminance_sigma");
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < half_a.size(); ++i) {
    if (!finite3(half_a.pixels[i]) || !finite3(half_b.pixels[i])) continue;
    const double d = lum(half_a.pixels[i]) - lum(half_b.pixels[i]);
    sum += d * d / 4.0;  // Var of the pixel's full mean, as in estimator_noise
    ++n;
  }
  return n ? std::sqrt(sum) / double(n) : 0.0;
}

Comparison compare(const Image& x_mean, const Image& x_half_a, const Image& x_half_b, const Image& y_mean,
                   const Image& y_half_a, const Image& y_half_b) {
  require_same_size(x_mean, y_mean, "compare");
  Comparison c;
  c.relmse = relmse(x_mean, y_mean);
  // Both noise levels are measured against y's mean, as relMSE(x, y) is.
  c.noise_x = estimator_noise(x_half_a, x_half_b, y_mean);
  c.noise_y = estimator_noise(y_half_a, y_half_b, y_mean);
  // x − y = (bias) + (x's noise) − (y's noise), independent: the expected
  // squared differences add.
  c.combined_noise = c.noise_x + c.noise_y;
  if (c.combined_noise > 0)
    c.relmse_over_noise = c.relmse / c.combined_noise;
  else
    c.relmse_over_noise = c.relmse > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  c.bias_relmse = std::max(0.0, c.relmse - c.combined_noise);
  c.mean_abs_error = mean_abs_error(x_mean, y_mean);
  c.mean_rel_error = mean_rel_error(x_mean, y_mean);
  c.energy_ratio = energy_ratio(x_mean, y_mean);
  // Ratio of two independent means: relative variances add.
  const double lx = mean_luminance(x_mean), ly = mean_luminance(y_mean);
  const double sx = mean_luminance_sigma(x_half_a, x_half_b), sy = mean_luminance_sigma(y_half_a, y_half_b);
  double rel2 = 0;
  if (lx > 0) rel2 += (sx / lx) * (sx / lx);
  if (ly > 0) rel2 += (sy / ly) * (sy / ly);
  c.energy_ratio_sigma = std::isfinite(c.energy_ratio) ? c.energy_ratio * std::sqrt(rel2) : 0.0;
  c.max_luminance_ratio = max_luminance_ratio(x_mean, y_mean);
  c.nonfinite_x = count_nonfinite(x_mean);
  c.nonfinite_y = count_nonfinite(y_mean);
  return c;
}

ComparisonVerdict Comparison::judge(double noise_factor, double energy_tolerance, double relmse_tolerance) const {
  ComparisonVerdict v;
  const double rel_tol = std::max(relmse_tolerance, 0.0);
  const double energy_error = std::abs(energy_ratio - 1.0);
  const auto fmt = [](double d) { return std::to_string(d); };
  // Definite failures first: noise cannot explain them.
  if (nonfinite_x || nonfinite_y) {
    v.reason = "non-finite values: " + std::to_string(nonfinite_x) + " in x, " + std::to_string(nonfinite_y) + " in y";
    return v;
  }
  if (!(relmse <= noise_factor * combined_noise + rel_tol)) {
    v.reason = "relMSE " + fmt(relmse) + " > " + fmt(noise_factor) + " x noise " + fmt(combined_noise) +
               (rel_tol > 0 ? " + tolerance " + fmt(rel_tol) : std::string());
    return v;
  }
  if (!(energy_error <= energy_tolerance + kNoiseMargin * energy_ratio_sigma)) {
    v.reason = "energy ratio " + fmt(energy_ratio) + " off by more than " + fmt(energy_tolerance) + " + " +
               fmt(kNoiseMargin) + " sigma (" + fmt(energy_ratio_sigma) + ")";
    return v;
  }
  // Then: is the noise small enough for a pass to mean anything?
  if (kNoiseMargin * energy_ratio_sigma > energy_tolerance) {
    v.inconclusive = true;
    v.reason = "inconclusive: energy ratio noise " + fmt(energy_ratio_sigma) + " (1 sigma) is not well below tolerance " +
               fmt(energy_tolerance);
    return v;
  }
  if (rel_tol > 0 && kNoiseMargin * combined_noise > rel_tol) {
    v.inconclusive = true;
    v.reason = "inconclusive: relMSE noise " + fmt(combined_noise) + " is not well below tolerance " + fmt(rel_tol);
    return v;
  }
  if (energy_error > energy_tolerance) {
    v.reason = "energy ratio " + fmt(energy_ratio) + " off by more than " + fmt(energy_tolerance);
    return v;
  }
  v.passed = true;
  return v;
}

}  // namespace gi
