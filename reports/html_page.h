// Building blocks of the HTML reports (nightly, sweep), which open offline
// from their folder, no server, no network. The sweeps' pages embed their
// few images as data: URIs; the nightly's page stays light at any suite
// size: thumbnails embedded (small JPEG or PNG), each linked to its full
// image beside the page, plots as SVG files beside it loaded only when
// scrolled to (loading="lazy"), links to the EXR evidence by relative path.
// A small script at the end checks that every image that loaded decoded and
// says so on the console (console.error) and in body attributes, which is
// what the headless-Chromium test reads; report.html#all loads the lazy ones
// at once, so that a test sees them all.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/gnuplot.h"

namespace gi {

std::string html_escape(const std::string& text);
std::string base64(const std::string& bytes);

// <img> of a file (PNG) as a data: URI, or a note saying why there is none.
std::string html_image_file(const std::filesystem::path& file, const std::string& alt);
// <img> of a plot's SVG, or the reason it has none.
std::string html_plot(const PlotResult& plot, const std::string& alt);

// A thumbnail of an image file (PNG) for the page: at most kThumbnailWidth
// pixels wide (never enlarged), the smaller of its JPEG and PNG encodings as
// a data: URI, in a link to `href` (the full image beside the page). A note
// when the file cannot be read.
constexpr int kThumbnailWidth = 192;
std::string html_thumbnail(const std::filesystem::path& file, const std::string& href, const std::string& alt);
// The thumbnail's encoded bytes and type ("image/jpeg" or "image/png"), empty
// when `file` is no readable image.
struct Thumbnail {
  std::string bytes, mime;
  int width = 0, height = 0;
};
Thumbnail make_thumbnail(const std::filesystem::path& file, int max_width = kThumbnailWidth);

// <img> of a plot's SVG file (PlotResult::file) at `src`, relative to the
// page, loaded lazily; or the reason it has none.
std::string html_plot_file(const PlotResult& plot, const std::string& src, const std::string& alt);
// A plot's SVG inline in the page (its points' hover text, Plot::hover_labels,
// shows only inline: a browser does not show an <img>'s titles).
std::string html_plot_inline(const PlotResult& plot, const std::string& alt);

// A number for a person, in fixed notation, never an exponent: 4 significant
// digits (1.258, 12.58, 0.001234), integers from 1000 on whole, and 5 digits
// and more grouped by thousands with a narrow no-break space (12 580).
std::string html_number(double v);
// html_number for JSON numbers (integers exactly, grouped from 5 digits);
// strings as they are, null as a dash.
std::string html_figure(const nlohmann::json& v);

// <table> with a header row; cells are already HTML.
std::string html_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                       const std::string& css_class = "");

// <span class="verdict pass|fail|…">text</span>
std::string html_verdict(const std::string& verdict);

// The whole page: style, title, body, self-check script.
std::string html_page(const std::string& title, const std::string& body);

}  // namespace gi
