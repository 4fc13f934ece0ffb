#include "reports/summary.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "reports/json_figures.h"

namespace gi {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = p * static_cast<double>(v.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(pos);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (v[hi] - v[lo]) * (pos - static_cast<double>(lo));
}

nlohmann::json timing_summary(const std::map<std::string, std::vector<double>>& per_pass_ms) {
  nlohmann::json passes = nlohmann::json::object();
  double total = 0.0;
  for (const auto& [name, ms] : per_pass_ms) {
    if (ms.empty()) continue;
    const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / static_cast<double>(ms.size());
    total += mean;
    passes[name] = {{"frames", ms.size()},
                    {"mean_ms", json_figure(mean)},
                    {"median_ms", json_figure(percentile(ms, 0.5))},
                    {"p95_ms", json_figure(percentile(ms, 0.95))},
                    {"min_ms", json_figure(*std::min_element(ms.begin(), ms.end()))},
                    {"max_ms", json_figure(*std::max_element(ms.begin(), ms.end()))}};
  }
  return {{"passes", passes}, {"total_mean_ms", json_figure(total)}};
}

double pipeline_ms_per_frame(const nlohmann::json& timings) {
  if (!timings.is_object() || !timings.contains("passes") || timings["passes"].empty()) return std::nan("");
  double ms = 0;
  for (const auto& [pass, stats] : timings["passes"].items()) {
    if (observation_pass(pass)) continue;
    ms += stats.contains("median_ms") && stats["median_ms"].is_number() ? stats["median_ms"].get<double>()
                                                                         : std::nan("");
  }
  return ms;
}

bool pass_per_chain(const std::string& name) {
  return name == "light_tiles" || name == "di_initial_temporal" || name == "di_spatial_shade" ||
         name == "gi_initial_temporal" || name == "gi_spatial_shade" || name == "specular_gi";
}

double one_chain_ms_per_frame(const nlohmann::json& timings, std::uint32_t chains) {
  if (!timings.is_object() || !timings.contains("passes") || timings["passes"].empty()) return std::nan("");
  const double per_chain = 1.0 / double(std::max(chains, 1u));
  double ms = 0;
  for (const auto& [pass, stats] : timings["passes"].items()) {
    if (observation_pass(pass)) continue;
    const double median = stats.contains("median_ms") && stats["median_ms"].is_number()
                              ? stats["median_ms"].get<double>()
                              : std::nan("");
    ms += pass_per_chain(pass) ? median * per_chain : median;
  }
  return ms;
}

nlohmann::json build_info() {
  return {{"giharness", "0.1.0"},
          {"compiler", std::string("g++ ") + __VERSION__},
#ifdef NDEBUG
          {"assertions", false},
#else
          {"assertions", true},
#endif
  };
}

}  // namespace gi
