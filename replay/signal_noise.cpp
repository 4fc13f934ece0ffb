#include "replay/signal_noise.h"

#include <cmath>

#include "core/metrics.h"
#include "reports/json_figures.h"

namespace gi {

void TemporalNoise::restart(std::uint32_t frame) {
  count_ = 0;
  first_ = frame;
}

nlohmann::json TemporalNoise::figures(const std::map<std::string, gpu::NoiseSums>& sums) const {
  nlohmann::json out = nlohmann::json::object();
  const auto output = sums.find("output");
  if (count_ < 8 || output == sums.end()) return out;
  const double n = double(count_);
  for (const auto& [name, s] : sums) {
    double total = 0;
    std::size_t values = 0;
    for (std::size_t i = 0; i < s.sum.size(); ++i) {
      const glm::dvec3 m = output->second.sum[i] / n;
      for (int c = 0; c < 3; ++c) {
        const double var = (s.sum_sq[i][c] - s.sum[i][c] * s.sum[i][c] / n) / (n - 1.0);
        if (!std::isfinite(var) || !std::isfinite(m[c])) continue;
        total += std::max(var, 0.0) / (m[c] * m[c] + kRelmseEpsilon);
        ++values;
      }
    }
    out[name] = json_figure(values ? total / double(values) : 0.0);
  }
  return out;
}

}  // namespace gi
