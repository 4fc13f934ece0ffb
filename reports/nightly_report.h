// The nightly's HTML report (DESIGN §10): <out>/report.html, one file that
// works offline. Overview table; every regression with metric, baseline,
// measured value and tolerance; speed against error over the suite; per
// scenario the checks with figures and limits, plots of every per-frame curve
// and the reference check's image triplets (GPU output, Embree reference,
// error map) as PNG previews linked to the EXR evidence.
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

namespace gi {

// Reads each scenario's summary.json under out_dir (rows of the suite
// summary), writes PNG previews under <out>/<scenario>/previews/ and gnuplot
// work files under <out>/plots/, and writes <out>/report.html. Returns its path.
std::filesystem::path write_nightly_report(const std::filesystem::path& out_dir, const nlohmann::json& suite_summary);

}  // namespace gi
