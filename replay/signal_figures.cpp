#include "replay/signal_figures.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/metrics.h"
#include "checks/reference_check.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

std::string pass_signal(const std::string& pass) {
  if (observation_pass(pass)) return "";
  if (pass == "light_tiles" || starts_with(pass, "di_")) return "di";
  if (starts_with(pass, "gi_") || starts_with(pass, "world_cache")) return "gi";
  if (starts_with(pass, "specular")) return "specular";
  return "shared";
}

nlohmann::json signal_ms(const nlohmann::json& timings, std::uint32_t chains) {
  std::map<std::string, double> ms;
  if (timings.is_object() && timings.contains("passes"))
    for (const auto& [pass, stats] : timings["passes"].items()) {
      const std::string signal = pass_signal(pass);
      if (signal.empty() || !stats.contains("median_ms") || !stats["median_ms"].is_number()) continue;
      ms[signal] += stats["median_ms"].get<double>() / (pass_per_chain(pass) ? double(std::max(chains, 1u)) : 1.0);
    }
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [signal, v] : ms) out[signal] = json_figure(v);
  return out;
}

nlohmann::json signal_bias(const ChainMeans& signal, const Image& ref_mean, const Image& ref_half_a,
                           const Image& ref_half_b) {
  Image mean(signal.a.width, signal.a.height);
  for (std::size_t i = 0; i < mean.size(); ++i) mean.pixels[i] = 0.5f * (signal.a.pixels[i] + signal.b.pixels[i]);
  return comparison_json(compare(mean, signal.a, signal.b, ref_mean, ref_half_a, ref_half_b));
}

ReferenceResult indirect_reference(const ReferenceResult& full, const ReferenceResult& direct) {
  ReferenceResult r;
  r.mean = difference_images(full.mean, direct.mean);
  r.half_a = difference_images(full.half_a, direct.half_a);
  r.half_b = difference_images(full.half_b, direct.half_b);
  r.seconds = full.seconds + direct.seconds;
  return r;
}

NoiseAdditivity chain_noise_additivity(const std::vector<Image>& a, const std::vector<Image>& b, const Image& m) {
  constexpr std::uint32_t kBlock = 8;
  NoiseAdditivity out;
  const std::uint32_t bx = (m.width + kBlock - 1) / kBlock, by = (m.height + kBlock - 1) / kBlock;
  std::vector<double> block_sum(std::size_t(bx) * by, 0.0);
  std::vector<std::size_t> block_count(block_sum.size(), 0);
  double output = 0, signals = 0, cross = 0;
  std::size_t n = 0;
  for (std::uint32_t y = 0; y < m.height; ++y)
    for (std::uint32_t x = 0; x < m.width; ++x) {
      const std::size_t i = std::size_t(y) * m.width + x;
      bool ok = finite(m.pixels[i]);
      for (std::size_t k = 0; k < a.size(); ++k) ok = ok && finite(a[k].pixels[i]) && finite(b[k].pixels[i]);
      if (!ok) continue;
      const std::size_t block = std::size_t(y / kBlock) * bx + x / kBlock;
      for (int c = 0; c < 3; ++c) {
        const double d = double(m.pixels[i][c]) * m.pixels[i][c] + kRelmseEpsilon;
        double total = 0, squares = 0;
        for (std::size_t k = 0; k < a.size(); ++k) {
          const double delta = double(a[k].pixels[i][c]) - double(b[k].pixels[i][c]);
          total += delta;
          squares += delta * delta;
        }
        // (Σ Δ)² / 2 = Σ Δ² / 2 + Σ_{j<k} Δj Δk
        const double cross_value = (total * total - squares) / 2.0 / d;
        output += total * total / 2.0 / d;
        signals += squares / 2.0 / d;
        cross += cross_value;
        block_sum[block] += cross_value;
        ++block_count[block];
        ++n;
      }
    }
  if (n == 0) return out;
  out.output = output / double(n);
  out.sum_of_signals = signals / double(n);
  out.cross_term = cross / double(n);
  // The standard error of the mean from the block means' spread.
  double s = 0, s2 = 0;
  std::size_t blocks = 0;
  for (std::size_t k = 0; k < block_sum.size(); ++k) {
    if (!block_count[k]) continue;
    const double v = block_sum[k] / double(block_count[k]);
    s += v;
    s2 += v * v;
    ++blocks;
  }
  if (blocks > 1) {
    const double mean = s / double(blocks);
    const double var = std::max(0.0, (s2 - double(blocks) * mean * mean) / double(blocks - 1));
    out.cross_term_standard_error = std::sqrt(var / double(blocks));
  }
  return out;
}

}  // namespace gi
