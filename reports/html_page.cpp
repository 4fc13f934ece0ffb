#include "reports/html_page.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include <fmt/format.h>
// libstb-dev's libstb (linked by gi_core): decode, resize, encode.
#include <stb/stb_image.h>
#include <stb/stb_image_resize.h>
#include <stb/stb_image_write.h>

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

Thumbnail make_thumbnail(const std::filesystem::path& file, int max_width) {
  Thumbnail t;
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(file.c_str(), &w, &h, &channels, 3);
  if (!pixels) return t;
  std::vector<unsigned char> rgb(pixels, pixels + std::size_t(w) * h * 3);
  stbi_image_free(pixels);
  if (w > max_width) {
    const int tw = max_width, th = std::max(1, int(std::lround(double(h) * tw / w)));
    std::vector<unsigned char> small(std::size_t(tw) * th * 3);
    if (!stbir_resize_uint8(rgb.data(), w, h, 0, small.data(), tw, th, 0, 3)) return t;
    rgb.swap(small);
    w = tw;
    h = th;
  }
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
  };
  std::string jpeg, png;
  stbi_write_jpg_to_func(append, &jpeg, w, h, 3, rgb.data(), 85);
  stbi_write_png_to_func(append, &png, w, h, 3, rgb.data(), w * 3);
  // Small images (a 32x32 test scene, an error map) are smaller, and sharp, as PNG.
  const bool use_png = !png.empty() && (jpeg.empty() || png.size() <= jpeg.size());
  t.bytes = use_png ? png : jpeg;
  t.mime = use_png ? "image/png" : "image/jpeg";
  t.width = w;
  t.height = h;
  if (t.bytes.empty()) t = {};
  return t;
}

std::string html_thumbnail(const std::filesystem::path& file, const std::string& href, const std::string& alt) {
  const Thumbnail t = make_thumbnail(file);
  if (t.bytes.empty()) return "<p class=\"note\">missing image " + html_escape(file.string()) + "</p>";
  return fmt::format("<a href=\"{}\"><img class=\"thumb\" alt=\"{}\" width=\"{}\" height=\"{}\" src=\"data:{};base64,{}\"></a>",
                     html_escape(href), html_escape(alt), kThumbnailWidth,
                     std::lround(double(t.height) * kThumbnailWidth / t.width), t.mime, base64(t.bytes));
}

std::string html_plot_file(const PlotResult& plot, const std::string& src, const std::string& alt) {
  if (plot.svg.empty() || plot.file.empty()) return "<p class=\"note\">no plot: " + html_escape(plot.error) + "</p>";
  return fmt::format("<a href=\"{0}\"><img class=\"plot\" loading=\"lazy\" width=\"{2}\" height=\"{3}\" alt=\"{1}\" "
                     "src=\"{0}\"></a>",
                     html_escape(src), html_escape(alt), kPlotWidth, kPlotHeight);
}

std::string html_plot_inline(const PlotResult& plot, const std::string& alt) {
  if (plot.svg.empty()) return "<p class=\"note\">no plot: " + html_escape(plot.error) + "</p>";
  // The document's prolog (<?xml?>, DOCTYPE) is no HTML: the <svg> element on.
  const std::size_t at = plot.svg.find("<svg");
  if (at == std::string::npos) return "<p class=\"note\">no plot: not an SVG document</p>";
  return "<figure class=\"plot\" role=\"img\" aria-label=\"" + html_escape(alt) + "\">" + plot.svg.substr(at) +
         "</figure>";
}

namespace {

// "12580" → "12 580" (U+202F) from 5 digits on; the sign and decimals stay.
std::string group_thousands(std::string s) {
  const std::size_t begin = s[0] == '-' || s[0] == '+' ? 1 : 0;
  const std::size_t end = std::min(s.find('.'), s.size());
  if (end - begin < 5) return s;
  for (std::size_t at = end; at > begin + 3; at -= 3) s.insert(at - 3, "\u202f");
  return s;
}

}  // namespace

std::string html_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "&minus;inf";
  if (v == 0.0) return "0";
  // 4 significant digits, in decimals: 3 after the first digit's place.
  const int place = int(std::floor(std::log10(std::fabs(v))));
  const int decimals = std::clamp(3 - place, 0, 20);
  std::string s = fmt::format("{:.{}f}", v, decimals);
  // Rounding up a place (9.9996 → "10.000"): one decimal fewer.
  if (decimals > 0 && std::fabs(std::stod(s)) >= std::pow(10.0, place + 1)) s = fmt::format("{:.{}f}", v, decimals - 1);
  if (s == "-0" || s.find_first_not_of("-0.") == std::string::npos) s = "0";  // below 10^-20
  return group_thousands(s);
}

std::string html_figure(const nlohmann::json& v) {
  if (v.is_null()) return "&ndash;";
  if (v.is_string()) return html_escape(v.get<std::string>());
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_number_integer() || v.is_number_unsigned()) return group_thousands(v.dump());
  if (v.is_number()) return html_number(v.get<double>());
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
img.thumb { width: 192px; height: auto; image-rendering: pixelated; border: 1px solid #999; }
img.plot { max-width: 760px; width: 100%; height: auto; }
figure.plot { margin: 0; max-width: 760px; } figure.plot svg { width: 100%; height: auto; }
.note { color: #777; font-style: italic; }
code, .small { font-size: 12px; }
)";
  static const char* check_script = R"(
if (location.hash === '#all')
  document.querySelectorAll('img[loading="lazy"]').forEach(function (img) { img.loading = 'eager'; });
window.addEventListener('load', function () {
  var images = document.querySelectorAll('img');
  var ok = 0, broken = 0, deferred = 0;
  images.forEach(function (img) {
    if (img.complete && img.naturalWidth > 0) { ok++; }
    else if (!img.complete && img.loading === 'lazy') { deferred++; }
    else { broken++; console.error('report: image did not load: ' + img.alt); }
  });
  document.body.setAttribute('data-images-ok', String(ok));
  document.body.setAttribute('data-images-broken', String(broken));
  document.body.setAttribute('data-images-deferred', String(deferred));
});
)";
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>{}</style>\n"
      "</head>\n<body>\n{}\n<script>{}</script>\n</body>\n</html>\n",
      html_escape(title), style, body, check_script);
}

}  // namespace gi
