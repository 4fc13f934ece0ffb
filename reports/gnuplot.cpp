#include "reports/gnuplot.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

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

bool all_positive(const Plot& p, bool x_axis) {
  for (const PlotSeries& s : p.series)
    for (const auto& [x, y] : s.points)
      if ((x_axis ? x : y) <= 0) return false;
  return true;
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
  gp << "set terminal svg size 760,300 noenhanced font 'DejaVu Sans,11' background rgb 'white'\n";
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
        for (char& ch : label) if (ch == '"') ch = '\'';
        d << fmt::format("{:.9g} {:.9g} \"{}\"\n", x, y, label);
        ++n;
      }
      if (n == 0) continue;
      clauses.push_back(fmt::format("{} using 1:2 with {} title {}", quoted(data.string()),
                                    series.lines ? "linespoints pointsize 0.5" : "points pointsize 1.5 pointtype 7",
                                    quoted(series.title)));
      if (!series.labels.empty())
        clauses.push_back(fmt::format("{} using 1:2:3 with labels offset char 1,0.6 font ',9' notitle",
                                      quoted(data.string())));
    }
    if (clauses.empty()) {
      results[i].error = "no finite data to plot";
      continue;
    }
    drawn[i] = true;
    gp << "reset\nset output " << quoted((work_dir / fmt::format("plot_{}.svg", i)).string()) << "\n";
    gp << "set title " << quoted(p.title) << "\nset xlabel " << quoted(p.xlabel) << "\nset ylabel "
       << quoted(p.ylabel) << "\nset grid\nset key outside right top\n";
    if (p.log_x && all_positive(p, true)) gp << "set logscale x\n";
    if (p.log_y && all_positive(p, false)) gp << "set logscale y\n";
    gp << "plot ";
    for (std::size_t c = 0; c < clauses.size(); ++c) gp << (c ? ", \\\n     " : "") << clauses[c];
    gp << "\nunset output\n";
  }
  gp.close();
  const std::filesystem::path log = work_dir / "gnuplot.log";
  const int rc = std::system(fmt::format("gnuplot {} > {} 2>&1", quoted(script.string()), quoted(log.string())).c_str());
  for (std::size_t i = 0; i < plots.size(); ++i) {
    if (!drawn[i]) continue;
    const std::filesystem::path svg = work_dir / fmt::format("plot_{}.svg", i);
    if (std::filesystem::exists(svg) && std::filesystem::file_size(svg) > 0) results[i].svg = read_all(svg);
    else results[i].error = fmt::format("gnuplot failed (exit {}); see {}", rc, log.string());
  }
  return results;
}

}  // namespace gi
