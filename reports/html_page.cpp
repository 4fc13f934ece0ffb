#include "reports/html_page.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "reports/junit.h"

namespace gi {

// XML's escaping is also valid HTML (&apos; included); one implementation.
std::string html_escape(const std::string& text) { return xml_escape(text); }

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned(static_cast<unsigned char>(bytes[i])) << 16) |
                       (unsigned(static_cast<unsigned char>(bytes[i + 1])) << 8) |
                       unsigned(static_cast<unsigned char>(bytes[i + 2]));
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = unsigned(static_cast<unsigned char>(bytes[i])) << 16;
    if (i + 1 < bytes.size()) v |= unsigned(static_cast<unsigned char>(bytes[i + 1])) << 8;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string html_image_file(const std::filesystem::path& file, const std::string& alt) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return "<p class=\"note\">missing image " + html_escape(file.string()) + "</p>";
  std::stringstream ss;
  ss << in.rdbuf();
  return fmt::format("<img class=\"preview\" alt=\"{}\" src=\"data:image/png;base64,{}\">", html_escape(alt),
                     base64(ss.str()));
}

std::string html_plot(const PlotResult& plot, const std::string& alt) {
  if (plot.svg.empty()) return "<p class=\"note\">no plot: " + html_escape(plot.error) + "</p>";
  return fmt::format("<img class=\"plot\" alt=\"{}\" src=\"data:image/svg+xml;base64,{}\">", html_escape(alt),
                     base64(plot.svg));
}

std::string html_figure(const nlohmann::json& v) {
  if (v.is_null()) return "&ndash;";
  if (v.is_string()) return html_escape(v.get<std::string>());
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number()) return fmt::format("{:.4g}", v.get<double>());
  return html_escape(v.dump());
}

std::string html_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                       const std::string& css_class) {
  std::string out = css_class.empty() ? "<table>" : "<table class=\"" + css_class + "\">";
  out += "<thead><tr>";
  for (const std::string& h : header) out += "<th>" + html_escape(h) + "</th>";
  out += "</tr></thead><tbody>\n";
  for (const auto& row : rows) {
    out += "<tr>";
    for (const std::string& cell : row) out += "<td>" + cell + "</td>";
    out += "</tr>\n";
  }
  return out + "</tbody></table>\n";
}

std::string html_verdict(const std::string& verdict) {
  std::string css;
  for (char ch : verdict) css += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '-';
  return "<span class=\"verdict " + css + "\">" + html_escape(verdict) + "</span>";
}

std::string html_page(const std::string& title, const std::string& body) {
  static const char* style = R"(
body { font-family: "DejaVu Sans", sans-serif; font-size: 14px; margin: 1.5em; color: #222; background: #fff; }
h1 { font-size: 1.5em; } h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #ccc; } h3 { font-size: 1.05em; }
table { border-collapse: collapse; margin: 0.5em 0 1em 0; }
th, td { border: 1px solid #ccc; padding: 3px 8px; text-align: left; vertical-align: top; }
th { background: #f0f0f0; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
.verdict { font-weight: bold; padding: 1px 6px; border-radius: 3px; }
.verdict.pass, .verdict.improved, .verdict.caught { background: #d7f5d7; color: #135e13; }
.verdict.fail, .verdict.regressed, .verdict.missed, .verdict.missing, .verdict.error, .verdict.bad-input, .verdict.crashed,
.verdict.timeout, .verdict.device-error { background: #fbd5d5; color: #8a1010; }
.verdict.flaky { background: #ffd9b3; color: #7a3b00; }
.verdict.inconclusive, .verdict.not-run, .verdict.interrupted, .verdict.no-baseline { background: #fff0c2; color: #6b5200; }
.verdict.unchanged { background: #e4ecf7; color: #22406b; }
.verdict.changed { background: #f3dcf7; color: #6a1b7a; }
.verdict.no-exact-baseline { background: #eeeeee; color: #555555; }
.triplet { display: flex; gap: 12px; flex-wrap: wrap; }
.triplet figure { margin: 0; } .triplet figcaption { font-size: 12px; color: #555; }
img.preview { width: 256px; image-rendering: pixelated; border: 1px solid #999; }
img.plot { max-width: 760px; width: 100%; }
.note { color: #777; font-style: italic; }
code, .small { font-size: 12px; }
)";
  static const char* check_script = R"(
window.addEventListener('load', function () {
  var images = document.querySelectorAll('img');
  var ok = 0, broken = 0;
  images.forEach(function (img) {
    if (img.complete && img.naturalWidth > 0) { ok++; }
    else { broken++; console.error('report: image did not load: ' + img.alt); }
  });
  document.body.setAttribute('data-images-ok', String(ok));
  document.body.setAttribute('data-images-broken', String(broken));
});
)";
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{}</style>\n"
      "</head>\n<body>\n{}\n<script>{}</script>\n</body>\n</html>\n",
      html_escape(title), style, body, check_script);
}

}  // namespace gi
