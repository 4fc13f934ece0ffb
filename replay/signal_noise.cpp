#include "replay/signal_noise.h"

#include <cmath>

#include "core/metrics.h"
#include "reports/json_figures.h"

namespace gi {

void TemporalNoise::restart(std::uint32_t frame) {
  sums_.clear();
  count_ = 0;
  first_ = frame;
}

void TemporalNoise::add(const std::map<std::string, const Image*>& signals) {
  for (const auto& [name, image] : signals) {
    Sums& s = sums_[name];
    if (s.sum.empty()) {
      s.sum.assign(image->size(), glm::dvec3(0.0));
      s.sum_sq.assign(image->size(), glm::dvec3(0.0));
    }
    for (std::size_t i = 0; i < image->size(); ++i) {
      const glm::dvec3 x(image->pixels[i]);
      s.sum[i] += x;
      s.sum_sq[i] += x * x;
    }
  }
  ++count_;
}

nlohmann::json TemporalNoise::figures() const {
  nlohmann::json out = nlohmann::json::object();
  const auto output = sums_.find("output");
  if (count_ < 8 || output == sums_.end()) return out;
  const double n = double(count_);
  for (const auto& [name, s] : sums_) {
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
