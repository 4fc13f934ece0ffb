// The nightly's HTML report (docs/design.md §10): <out>/report.html, the front
// door of a night, opened offline from the out folder (no server). Overview
// table; every regression with metric, baseline, measured value and
// tolerance; speed against error over the suite (points' names on hover and
// in a table); per scenario the checks with figures and limits, plots of
// every per-frame curve and the reference check's image triplets (GPU
// output, Embree reference, error map) linked to the EXR evidence.
//
// Light at any suite size: only thumbnails are in the page (html_thumbnail,
// a few KB each), each linked to its full PNG beside it; the per-frame plots
// are SVG files under <out>/plots/ that the page loads lazily. A scenario
// adds some 10 KB of page (tests/nightly_report_test.cpp bounds it).
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

namespace gi {

// Reads each scenario's summary.json under out_dir (rows of the suite
// summary), writes PNG previews under <out>/<scenario>/previews/, the plots
// (and gnuplot's work files) under <out>/plots/, and writes <out>/report.html,
// each file under a temporary name renamed into place. Returns its path.
std::filesystem::path write_nightly_report(const std::filesystem::path& out_dir, const nlohmann::json& suite_summary);

}  // namespace gi
