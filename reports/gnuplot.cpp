#include "reports/gnuplot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

namespace gi {
namespace {

// gnuplot single-quoted strings: a quote is doubled; nothing else is special.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("''") : std::string(1, ch);
  return out + "'";
}

std::string read_all(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A hover text gnuplot passes through as it is: no quote, backslash or XML
// special character (they would need escaping in its SVG's attribute).
std::string plain_text(const std::string& s) {
  std::string out;
  for (unsigned char ch : s)
    if (ch == '\'')
      out += "\u2019";  // ’
    else
      out += ch >= 0x80 || std::isalnum(ch) || std::string_view(" _.,:;()/%+=-#*").find(char(ch)) != std::string_view::npos
               ? char(ch)
               : '_';
  return out;
}

// gnuplot's hypertext points call its mouse script (gnuplot_svg.js, which a
// report does not have): each becomes a plain <title>, which a browser shows
// on hover; the document's "Gnuplot" and per-plot "gnuplot_plot_<n>" titles
// would show over everything else, and go.
std::string hover_titles(const std::string& svg) {
  static const std::regex hypertext(
      R"re(<g onmousemove="gnuplot_svg\.showHypertext\(evt,'([^']*)'\)" onmouseout="gnuplot_svg\.hideHypertext\(\)"><title> </title>)re");
  static const std::regex plot_title(R"re(<title>(gnuplot_plot_\d+|Gnuplot)</title>)re");
  return std::regex_replace(std::regex_replace(svg, hypertext, "<g><title>$1</title>"), plot_title, "");
}

bool all_positive(const Plot& p, bool x_axis) {
  for (const PlotSeries& s : p.series)
    for (const auto& [x, y] : s.points)
      if ((x_axis ? x : y) <= 0) return false;
  return true;
}

// Tick labels of a log axis a person reads: 0.01 to 10000 as they are, a
// wider range as powers of ten ("10^-6", not gnuplot's "0.0000010" or "1e-06").
std::string log_tick_format(const Plot& p, bool x_axis) {
  double lo = INFINITY, hi = 0;
  for (const PlotSeries& s : p.series)
    for (const auto& [x, y] : s.points) {
      const double v = x_axis ? x : y;
      if (std::isfinite(v) && v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
    }
  return lo >= 0.01 && hi <= 1e4 ? "%g" : "10^%L";
}

// Long series titles take the plot's width when the key is beside it.
bool long_titles(const Plot& p) {
  for (const PlotSeries& s : p.series)
    if (s.title.size() > 30) return true;
  return false;
}

}  // namespace

bool gnuplot_available() { return std::system("gnuplot --version > /dev/null 2>&1") == 0; }

std::vector<PlotResult> render_plots(const std::vector<Plot>& plots, const std::filesystem::path& work_dir) {
  std::vector<PlotResult> results(plots.size());
  if (plots.empty()) return results;
  if (!gnuplot_available()) {
    for (PlotResult& r : results) r.error = "gnuplot is not installed (Debian package gnuplot-nox)";
    return results;
  }
  std::filesystem::create_directories(work_dir);
  const std::filesystem::path script = work_dir / "plots.gp";
  std::ofstream gp(script);
  gp << "set terminal svg size " << kPlotWidth << "," << kPlotHeight
     << " noenhanced font 'DejaVu Sans,11' background rgb 'white'\n";
  std::vector<bool> drawn(plots.size(), false);
  for (std::size_t i = 0; i < plots.size(); ++i) {
    const Plot& p = plots[i];
    std::vector<std::string> clauses;
    for (std::size_t s = 0; s < p.series.size(); ++s) {
      const PlotSeries& series = p.series[s];
      const std::filesystem::path data = work_dir / fmt::format("plot_{}_{}.dat", i, s);
      std::ofstream d(data);
      std::size_t n = 0;
      for (std::size_t k = 0; k < series.points.size(); ++k) {
        const auto [x, y] = series.points[k];
        if (!std::isfinite(x) || !std::isfinite(y)) continue;
        std::string label = k < series.labels.size() ? series.labels[k] : "";
        if (p.hover_labels) label = plain_text(label);
        for (char& ch : label) if (ch == '"') ch = '\'';
        d << fmt::format("{:.9g} {:.9g} \"{}\"\n", x, y, label);
        ++n;
      }
      if (n == 0) continue;
      const std::string style = series.lines ? "linespoints pointsize 0.5" : "points pointsize 1.5 pointtype 7";
      if (p.hover_labels && !series.labels.empty()) {
        // The visible points (and the key), then the same points again as
        // hypertext, one colour (linetype) per series.
        clauses.push_back(fmt::format("{} using 1:2 with {} linetype {} title {}", quoted(data.string()), style, s + 1,
                                      quoted(series.title)));
        clauses.push_back(fmt::format("{} using 1:2:3 with labels hypertext point pointtype 7 pointsize 1.5 linetype {} "
                                      "notitle",
                                      quoted(data.string()), s + 1));
        continue;
      }
      clauses.push_back(fmt::format("{} using 1:2 with {} title {}", quoted(data.string()), style, quoted(series.title)));
      if (!series.labels.empty())
        clauses.push_back(fmt::format("{} using 1:2:3 with labels offset char 1,0.6 font ',9' notitle",
                                      quoted(data.string())));
    }
    if (clauses.empty()) {
      results[i].error = "no finite data to plot";
      continue;
    }
    drawn[i] = true;
    gp << "reset\nset output " << quoted((work_dir / fmt::format("plot_{}.svg.tmp", i)).string()) << "\n";
    gp << "set title " << quoted(p.title) << "\nset xlabel " << quoted(p.xlabel) << "\nset ylabel "
       << quoted(p.ylabel) << "\nset grid\n" << (long_titles(p) ? "set key below\n" : "set key outside right top\n");
    if (p.log_x && all_positive(p, true)) gp << "set logscale x\nset format x " << quoted(log_tick_format(p, true)) << "\n";
    if (p.log_y && all_positive(p, false)) gp << "set logscale y\nset format y " << quoted(log_tick_format(p, false)) << "\n";
    gp << "plot ";
    for (std::size_t c = 0; c < clauses.size(); ++c) gp << (c ? ", \\\n     " : "") << clauses[c];
    gp << "\nunset output\n";
  }
  gp.close();
  const std::filesystem::path log = work_dir / "gnuplot.log";
  const int rc = std::system(fmt::format("gnuplot {} > {} 2>&1", quoted(script.string()), quoted(log.string())).c_str());
  for (std::size_t i = 0; i < plots.size(); ++i) {
    if (!drawn[i]) continue;
    const std::filesystem::path svg = work_dir / fmt::format("plot_{}.svg", i), tmp = svg.string() + ".tmp";
    std::error_code ec;
    // gnuplot closes each output at "unset output": a complete file, renamed
    // into place (a hover plot is rewritten first, atomically too).
    if (std::filesystem::exists(tmp, ec) && std::filesystem::file_size(tmp, ec) > 0) {
      results[i].svg = read_all(tmp);
      if (plots[i].hover_labels) {
        results[i].svg = hover_titles(results[i].svg);
        std::ofstream(tmp, std::ios::binary | std::ios::trunc) << results[i].svg;
      }
      std::filesystem::rename(tmp, svg, ec);
      if (ec) {
        results[i].svg.clear();
        results[i].error = fmt::format("cannot rename {}: {}", tmp.string(), ec.message());
        continue;
      }
      results[i].file = svg;
    } else {
      std::filesystem::remove(tmp, ec);
      results[i].error = fmt::format("gnuplot failed (exit {}); see {}", rc, log.string());
    }
  }
  return results;
}

}  // namespace gi
