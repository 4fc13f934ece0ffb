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

double student_t_quantile(double p, std::uint32_t dof) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("student_t_quantile: p outside (0, 1)");
  if (p < 0.5) return -student_t_quantile(1.0 - p, dof);
  const double nu = dof;
  // log of the density's normalising constant (0: the normal's).
  const double log_c = dof == 0 ? -0.5 * std::log(2.0 * M_PI)
                                : std::lgamma((nu + 1.0) / 2.0) - std::lgamma(nu / 2.0) - 0.5 * std::log(nu * M_PI);
  const auto density = [&](double t) {
    return std::exp(dof == 0 ? log_c - 0.5 * t * t : log_c - (nu + 1.0) / 2.0 * std::log1p(t * t / nu));
  };
  // CDF(t) − 1/2 by Simpson's rule on [0, t] (fine steps: the quantiles used here are below ~300).
  const auto upper_half = [&](double t) {
    const int n = 20000;
    const double h = t / n;
    double sum = density(0.0) + density(t);
    for (int i = 1; i < n; ++i) sum += density(i * h) * (i % 2 ? 4.0 : 2.0);
    return sum * h / 3.0;
  };
  double lo = 0.0, hi = 1.0;
  while (upper_half(hi) < p - 0.5) hi *= 2.0;
  for (int i = 0; i < 100 && hi - lo > 1e-9 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (upper_half(mid) < p - 0.5 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
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

double Comparison::noise_margin(std::uint32_t dof) {
  return dof == 0 ? kNoiseMargin : student_t_quantile(0.5 + std::erf(kNoiseMargin / std::sqrt(2.0)) / 2.0, dof);
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
  // The margin of the same two-sided false-alarm rate as kNoiseMargin σ of a
  // normal, for an energy σ estimated with energy_dof degrees of freedom.
  const double margin = noise_margin(energy_dof);
  if (!(energy_error <= energy_tolerance + margin * energy_ratio_sigma)) {
    v.reason = "energy ratio " + fmt(energy_ratio) + " off by more than " + fmt(energy_tolerance) + " + " +
               fmt(margin) + " sigma (" + fmt(energy_ratio_sigma) +
               (energy_dof ? ", " + std::to_string(energy_dof) + " degrees of freedom)" : ")");
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

Comparison compare_chains(const std::vector<Image>& chains, const Image& y_mean, const Image& y_half_a,
                          const Image& y_half_b) {
  if (chains.size() < 2) throw std::invalid_argument("compare_chains: fewer than 2 chains");
  const std::size_t k = chains.size();
  Image x(y_mean.width, y_mean.height);
  for (const Image& c : chains) {
    require_same_size(c, y_mean, "compare_chains");
    for (std::size_t i = 0; i < x.size(); ++i) x.pixels[i] += c.pixels[i] / float(k);
  }
  // The two-chain case is exactly compare() with the chains as halves.
  Comparison out = compare(x, chains[0], chains[1], y_mean, y_half_a, y_half_b);
  if (k > 2) {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      bool finite = finite3(y_mean.pixels[i]);
      for (const Image& c : chains) finite = finite && finite3(c.pixels[i]);
      if (!finite) continue;
      for (int ch = 0; ch < 3; ++ch) {
        double m = 0, s2 = 0;
        for (const Image& c : chains) m += double(c.pixels[i][ch]) / double(k);
        for (const Image& c : chains) s2 += (c.pixels[i][ch] - m) * (c.pixels[i][ch] - m) / double(k - 1);
        const double r = y_mean.pixels[i][ch];
        sum += s2 / double(k) / (r * r + kRelmseEpsilon);
      }
      n += 3;
    }
    out.noise_x = n ? sum / double(n) : 0.0;
    out.combined_noise = out.noise_x + out.noise_y;
    out.relmse_over_noise = out.combined_noise > 0 ? out.relmse / out.combined_noise
                                                   : (out.relmse > 0 ? std::numeric_limits<double>::infinity() : 0.0);
    out.bias_relmse = std::max(0.0, out.relmse - out.combined_noise);
  }
  // Energy: the chains' mean luminances are K independent draws.
  double m = 0, s2 = 0;
  std::vector<double> l;
  for (const Image& c : chains) l.push_back(mean_luminance(c));
  for (double v : l) m += v / double(k);
  for (double v : l) s2 += (v - m) * (v - m) / double(k - 1);
  const double lx = mean_luminance(x), ly = mean_luminance(y_mean);
  const double sx = std::sqrt(s2 / double(k)), sy = mean_luminance_sigma(y_half_a, y_half_b);
  double rel2 = 0;
  if (lx > 0) rel2 += (sx / lx) * (sx / lx);
  if (ly > 0) rel2 += (sy / ly) * (sy / ly);
  out.energy_ratio_sigma = std::isfinite(out.energy_ratio) ? out.energy_ratio * std::sqrt(rel2) : 0.0;
  out.energy_dof = std::uint32_t(k - 1);
  return out;
}

}  // namespace gi
