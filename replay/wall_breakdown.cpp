#include "replay/wall_breakdown.h"

#include <algorithm>
#include <map>
#include <vector>

#include <fmt/format.h>

#include "core/phase_clock.h"
#include "reports/json_figures.h"
#include "reports/summary.h"

namespace gi {
namespace {

constexpr const char* kMethod =
    "seconds: wall time per phase, a phase inside another counted in the inner one (core/phase_clock.h); other: the "
    "rest of the wall (device creation, the checks' results, failure captures). first_dispatch_ms: per pass, frame 0's pass time "
    "minus the median of its later frames' (passes timed on at least 3 frames; 0 where not above): on a device that "
    "compiles a pipeline when it first runs (lavapipe), the driver's compile, inside frames";

// Per pass: the first frame's time above the median of the later ones.
nlohmann::json first_dispatch_ms(const nlohmann::json& frames) {
  nlohmann::json out = nlohmann::json::object();
  if (!frames.is_array() || frames.size() < 3 || !frames.front().contains("pass_ms")) return out;
  for (const auto& [pass, first] : frames.front()["pass_ms"].items()) {
    if (!first.is_number()) continue;
    std::vector<double> later;
    for (std::size_t i = 1; i < frames.size(); ++i) {
      const nlohmann::json& ms = frames[i].value("pass_ms", nlohmann::json::object());
      if (ms.contains(pass) && ms[pass].is_number()) later.push_back(ms[pass].get<double>());
    }
    if (later.size() < 2) continue;
    out[pass] = json_figure(std::max(0.0, first.get<double>() - percentile(later, 0.5)));
  }
  return out;
}

double sum_of(const nlohmann::json& figures) {
  double s = 0;
  for (const auto& [k, v] : figures.items())
    if (v.is_number()) s += v.get<double>();
  return s;
}

}  // namespace

nlohmann::json wall_breakdown(double wall_seconds, const nlohmann::json& frames,
                              const std::map<std::string, double>& phases_at_start) {
  nlohmann::json seconds = nlohmann::json::object();
  double phases = 0;
  for (const auto& [phase, total] : phase_seconds()) {
    const auto before = phases_at_start.find(phase);
    const double s = total - (before == phases_at_start.end() ? 0.0 : before->second);
    if (s <= 0.0) continue;  // not in this run
    seconds[phase] = json_figure(s);
    phases += s;
  }
  seconds["other"] = json_figure(std::max(0.0, wall_seconds - phases));
  const nlohmann::json first = first_dispatch_ms(frames);
  return {{"wall_seconds", json_figure(wall_seconds)},
          {"seconds", seconds},
          {"first_dispatch_ms", first},
          {"first_dispatch_seconds", json_figure(sum_of(first) / 1000.0)},
          {"method", kMethod}};
}

void add_wall_breakdown(nlohmann::json& total, const nlohmann::json& run) {
  if (!run.is_object() || !run.contains("seconds")) return;
  if (!total.is_object())
    total = {{"wall_seconds", 0.0}, {"seconds", nlohmann::json::object()}, {"first_dispatch_ms", nlohmann::json::object()},
             {"first_dispatch_seconds", 0.0}, {"runs", 0}, {"method", run.value("method", "")}};
  auto add = [](nlohmann::json& to, const nlohmann::json& from) {
    for (const auto& [k, v] : from.items())
      if (v.is_number()) to[k] = json_figure(to.value(k, 0.0) + v.get<double>());
  };
  total["wall_seconds"] = json_figure(total["wall_seconds"].get<double>() + run.value("wall_seconds", 0.0));
  total["first_dispatch_seconds"] =
      json_figure(total["first_dispatch_seconds"].get<double>() + run.value("first_dispatch_seconds", 0.0));
  add(total["seconds"], run["seconds"]);
  add(total["first_dispatch_ms"], run.value("first_dispatch_ms", nlohmann::json::object()));
  total["runs"] = total["runs"].get<int>() + 1;
}

std::string wall_breakdown_line(const nlohmann::json& b) {
  std::string line = fmt::format("wall {:.1f} s:", b.value("wall_seconds", 0.0));
  const nlohmann::json& seconds = b["seconds"];
  std::vector<std::pair<double, std::string>> parts;
  for (const auto& [phase, s] : seconds.items()) parts.emplace_back(s.get<double>(), phase);
  std::sort(parts.rbegin(), parts.rend());
  for (const auto& [s, phase] : parts) {
    line += fmt::format(" {} {:.1f} s", phase, s);
    if (phase == phase::kFrames && b.value("first_dispatch_seconds", 0.0) > 0.0)
      line += fmt::format(" (first-dispatch compile ~{:.1f} s)", b["first_dispatch_seconds"].get<double>());
    line += ",";
  }
  line.pop_back();
  // The slowest first dispatch names the shader to look at.
  const nlohmann::json& first = b.value("first_dispatch_ms", nlohmann::json::object());
  std::string slowest;
  double slowest_ms = 0;
  for (const auto& [pass, ms] : first.items())
    if (ms.get<double>() > slowest_ms) slowest_ms = ms.get<double>(), slowest = pass;
  if (slowest_ms >= 1000.0) line += fmt::format("; slowest first dispatch {} {:.1f} s", slowest, slowest_ms / 1000.0);
  return line;
}

}  // namespace gi
