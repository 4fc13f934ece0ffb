// Building blocks of the self-contained HTML reports (nightly, sweep): one
// file, no network, images and plots embedded as data: URIs, links to the
// EXR evidence by relative path. A small script at the end checks that every
// embedded image decoded and says so on the console (console.error) and in
// body attributes, which is what the headless-Chromium test reads.
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

// A number for a person: 4 significant digits; strings as they are.
std::string html_figure(const nlohmann::json& v);

// <table> with a header row; cells are already HTML.
std::string html_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                       const std::string& css_class = "");

// <span class="verdict pass|fail|…">text</span>
std::string html_verdict(const std::string& verdict);

// The whole page: style, title, body, self-check script.
std::string html_page(const std::string& title, const std::string& body);

}  // namespace gi
