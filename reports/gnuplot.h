// Plots for reports, drawn by gnuplot (Debian's gnuplot-nox) as SVG: the
// report embeds or links the files, so no chart code lives here — only the
// data files and the gnuplot script. Every plot of a report goes through one
// gnuplot process (one start-up, ~50 ms, for dozens of plots).
#pragma once
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace gi {

// Every plot's size in SVG pixels.
constexpr int kPlotWidth = 760, kPlotHeight = 300;

struct PlotSeries {
  std::string title;
  std::vector<std::pair<double, double>> points;  // non-finite points are dropped
  std::vector<std::string> labels;                // optional, one per point, drawn next to it
  bool lines = true;                              // false: points only (scatter)
};

struct Plot {
  std::string title, xlabel, ylabel;
  bool log_x = false, log_y = false;  // ignored when a value is ≤ 0
  std::vector<PlotSeries> series;
  // The labels as each point's hover text (an SVG <title>, no script) instead
  // of text drawn next to it: a crowded scatter's labels never pile up. Shown
  // where the SVG is inline in a page (html_plot_inline).
  bool hover_labels = false;
};

struct PlotResult {
  std::string svg;             // the SVG document, empty on failure
  std::filesystem::path file;  // where it is (work_dir/plot_<i>.svg)
  std::string error;           // why there is no SVG
};

// Renders every plot (work_dir holds the data, script and SVG files and is
// left for inspection; each SVG is written under a temporary name and renamed
// into place). Without gnuplot every result has an error saying so.
std::vector<PlotResult> render_plots(const std::vector<Plot>& plots, const std::filesystem::path& work_dir);

bool gnuplot_available();

}  // namespace gi
