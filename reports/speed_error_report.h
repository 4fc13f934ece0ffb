// The nightly report's "Speed against error": one point per
// scenario (reference mode: the last compared frame's accumulated image;
// realtime: one frame of the output), the path tracers at each realtime
// scenario's ms/frame (summary.json "equal_time", replay/equal_time.h), a
// table of those per scene with the equal-error time ratios, and the
// per-signal figures (noise, bias, ms).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/gnuplot.h"

namespace gi {

struct NamedSummary {
  std::string name;
  const nlohmann::json* summary;
};

// The scatter of error against ms/frame.
Plot speed_against_error_plot(const std::vector<NamedSummary>& runs);

// The tables under the plot (HTML): equal time per realtime scene, then the
// per-signal figures; a sentence when no run measured them.
std::string speed_against_error_tables(const std::vector<NamedSummary>& runs);

}  // namespace gi
