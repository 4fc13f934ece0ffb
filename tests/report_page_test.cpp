// The nightly's page as a front door, in process (no device, no giharness
// process; gnuplot draws): numbers in fixed notation for people, a page
// that stays light per scenario however many frames, plots and images a
// scenario has (thumbnails in the page, full images and plots as files
// beside it, every link resolving inside the folder), and a speed-against-
// error scatter whose scenario names never pile up (hover text, a table).
// The browser's view of a real night is report_html_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <regex>
#include <set>

#include <fmt/format.h>

#include "core/exr_io.h"
#include "core/png_preview.h"
#include "reports/gnuplot.h"
#include "reports/html_page.h"
#include "reports/nightly_report.h"
#include "tests/test_support.h"

namespace gi {
namespace {

using nlohmann::json;

const std::string kGroup = "\u202f";  // the thousands separator: a narrow no-break space

TEST(ReportNumbers, FixedNotationWithFourSignificantDigits) {
  const std::vector<std::pair<double, std::string>> cases = {
      {12580.4, "12" + kGroup + "580"},
      {-12580.0, "-12" + kGroup + "580"},
      {1258.04, "1258"},
      {125.804, "125.8"},
      {12.5804, "12.58"},
      {1.25804, "1.258"},
      {0.0125804, "0.01258"},
      {1.258e-05, "0.00001258"},
      {2.0, "2.000"},
      {9.99996, "10.00"},
      {0.0, "0"},
      {1e15, "1" + kGroup + "000" + kGroup + "000" + kGroup + "000" + kGroup + "000" + kGroup + "000"},
  };
  for (const auto& [v, expected] : cases) EXPECT_EQ(html_figure(json(v)), expected) << v;
  // JSON integers: whole, grouped from 5 digits.
  EXPECT_EQ(html_figure(json(12580)), "12" + kGroup + "580");
  EXPECT_EQ(html_figure(json(1041)), "1041");
  EXPECT_EQ(html_figure(json(-7)), "-7");
}

// Every magnitude a report meets: never an exponent, and the digits shown
// are the value's to 4 significant digits.
TEST(ReportNumbers, NoExponentAtAnyMagnitude) {
  for (int exponent = -15; exponent <= 15; ++exponent)
    for (double mantissa : {1.0, 1.23456, 4.99999, 9.87654, 9.99999}) {
      const double v = mantissa * std::pow(10.0, exponent);
      const std::string text = html_figure(json(v));
      EXPECT_EQ(text.find_first_of("eE"), std::string::npos) << v << " → " << text;
      std::string digits;
      for (char ch : text)
        if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-') digits += ch;
      EXPECT_NEAR(std::stod(digits) / v, 1.0, 5.1e-4) << v << " → " << text;
    }
}

// ---- a synthetic night: what each scenario brings to the page ---------------

// A render's look: smooth shading with a few percent of per-pixel noise (a
// real night's thumbnails: 2 to 11 KB of base64 each).
Image noise_image(std::uint32_t w, std::uint32_t h, unsigned seed) {
  Image img(w, h);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.04f, 0.04f);
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const float fx = float(x) / float(w), fy = float(y) / float(h);
      img.at(x, y) = glm::vec3(0.6f * fx, 0.5f * fy, 0.3f) + glm::vec3(u(rng), u(rng), u(rng));
    }
  return img;
}

// A scenario as a long realtime night leaves it: 360 frames of several
// curves and eight passes, a reference check with its EXR evidence (three
// 320x180 layers), a capture with its PNG preview; total 12.58 s a frame.
json scenario_row(const std::filesystem::path& out, const std::string& name, unsigned seed) {
  const std::filesystem::path dir = out / name;
  std::filesystem::create_directories(dir / "reference");
  std::filesystem::create_directories(dir / "captures/frame_00359");
  const Image gpu = noise_image(320, 180, seed), embree = noise_image(320, 180, seed + 1),
              error = noise_image(320, 180, seed + 2);
  write_exr(dir / "reference/frame_00359.exr", {{"gpu", &gpu}, {"embree", &embree}, {"error", &error}});
  write_exr(dir / "captures/frame_00359/images.exr", {{"output", &gpu}});
  write_png_preview(dir / "captures/frame_00359/images.png", gpu);
  json frames = json::array();
  for (int f = 0; f < 360; ++f) {
    json pass_ms = json::object();
    for (int p = 0; p < 8; ++p) pass_ms[fmt::format("pass_{}", p)] = 1500.0 + 17.0 * p + std::sin(f * 0.1 + p);
    frames.push_back({{"frame", f},
                      {"mean_luminance", 0.2 + 0.001 * std::sin(f * 0.05)},
                      {"active_cells", 4000 + f},
                      {"lag", 0.5 * f},
                      {"nonfinite_pixels", 0},
                      {"pass_ms", pass_ms}});
  }
  json passes = json::object();
  for (int p = 0; p < 8; ++p) passes[fmt::format("pass_{}", p)] = {{"median_ms", 1572.55}, {"mean_ms", 1572.55}};
  const json summary = {
      {"scenario", {{"file", name + ".json"}}},
      {"resolved", {{"resolution", {320, 180}}, {"frames", 360}, {"seed", 0}, {"mode", "realtime"}}},
      {"frames", frames},
      {"timings", {{"passes", passes}, {"total_mean_ms", 12580.4}}},
      {"checks",
       json::array({{{"name", "reference"},
                     {"verdict", "pass"},
                     {"message", "within its limit"},
                     {"figures",
                      {{"relmse", 1.258e-05},
                       {"frames", json::array({{{"frame", 359}, {"relmse", 1.258e-05}, {"combined_noise", 2.5e-05},
                                                {"per_frame", {{"relmse", 0.003 + 0.0001 * seed}}}}})}}},
                     {"limits", {{"max_relmse", 0.001}}},
                     {"evidence", json::array({"reference/frame_00359.exr"})}}})},
      {"captures", json::array({"captures/frame_00359/images.exr"})},
  };
  std::ofstream(dir / "summary.json") << summary.dump();
  return {{"name", name}, {"file", name + ".json"}, {"summary", name + "/summary.json"}, {"status", "complete"},
          {"verdict", "pass"}, {"wall_seconds", 754.2}, {"checks", json::array({{{"name", "reference"}, {"verdict", "pass"}}})}};
}

// The values of every attr="..." in a page (no std::regex over it: a
// megabyte data: URI overflows libstdc++'s recursive matcher).
std::vector<std::string> attribute_values(const std::string& html, const std::string& attr) {
  std::vector<std::string> out;
  const std::string key = " " + attr + "=\"";
  for (std::size_t at = html.find(key); at != std::string::npos; at = html.find(key, at + 1)) {
    const std::size_t begin = at + key.size(), end = html.find('"', begin);
    if (end == std::string::npos) break;
    out.push_back(html.substr(begin, end - begin));
  }
  return out;
}

// The page less its inline SVG and data: URIs: what is text and tables.
std::string page_text(std::string html) {
  for (std::size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at)) {
    const std::size_t end = html.find("</svg>", at);
    html.erase(at, end == std::string::npos ? std::string::npos : end + 6 - at);
  }
  for (std::size_t at = html.find("\"data:"); at != std::string::npos; at = html.find("\"data:", at + 1))
    html.erase(at + 1, html.find('"', at + 1) - at - 1);
  return html;
}

struct Night {
  std::filesystem::path report;
  std::string html;
};

Night write_night(const test::TempDir& dir, std::size_t scenarios) {
  const std::filesystem::path out = dir.path() / fmt::format("night_{}", scenarios);
  json suite = {{"suite", "synthetic"}, {"verdict", "pass"}, {"exit_code", 0}, {"wall_seconds", 12580.4},
                {"scenarios", json::array()}};
  for (std::size_t i = 0; i < scenarios; ++i)
    suite["scenarios"].push_back(scenario_row(out, fmt::format("scenario_{:02d}", i), unsigned(10 * i)));
  Night night;
  night.report = write_nightly_report(out, suite);
  night.html = test::read_text(night.report);
  return night;
}

// The page grows by a bounded amount per scenario however much a scenario
// has (55 such scenarios: well under the 5 MB a front door may weigh); the
// plots are SVG files beside it, the full images too, not in the page.
TEST(ReportPage, StaysLightPerScenario) {
  ASSERT_TRUE(gnuplot_available()) << "install Debian's gnuplot-nox";
  test::TempDir dir("report-page-size");
  const Night two = write_night(dir, 2), eight = write_night(dir, 8);
  const double per_scenario = double(eight.html.size() - two.html.size()) / 6.0;
  RecordProperty("page_bytes_per_scenario", std::to_string(std::lround(per_scenario)));
  EXPECT_LT(per_scenario, 40e3) << "bytes of page per scenario";
  EXPECT_LT(eight.html.size(), 8 * 40e3 + 60e3);
  EXPECT_LT(55 * per_scenario + double(two.html.size()), 5e6) << "a default suite's page";
  EXPECT_EQ(eight.html.find("data:image/svg"), std::string::npos) << "plots are files beside the page";
  // Thumbnails only: each embedded image is small.
  std::size_t thumbnails = 0;
  for (const std::string& src : attribute_values(eight.html, "src")) {
    if (src.rfind("data:", 0) != 0) continue;
    ++thumbnails;
    EXPECT_TRUE(src.rfind("data:image/jpeg;base64,", 0) == 0 || src.rfind("data:image/png;base64,", 0) == 0)
        << src.substr(0, 40);
    EXPECT_LT(src.size(), 24u * 1024) << "a thumbnail of " << src.size() << " bytes";
  }
  EXPECT_EQ(thumbnails, 8u * 4u);  // gpu, embree, error, capture
}

// Offline from the folder: every file the page loads or links is there,
// relative to it (no absolute path, no server).
TEST(ReportPage, EveryLinkAndImageResolvesInsideTheFolder) {
  ASSERT_TRUE(gnuplot_available()) << "install Debian's gnuplot-nox";
  test::TempDir dir("report-page-links");
  const Night night = write_night(dir, 2);
  std::vector<std::string> targets = attribute_values(night.html, "src");
  for (const std::string& href : attribute_values(night.html, "href")) targets.push_back(href);
  std::size_t files = 0, plots = 0;
  for (const std::string& target : targets) {
    if (target.empty() || target[0] == '#' || target.rfind("data:", 0) == 0) continue;
    ++files;
    plots += target.rfind("plots/", 0) == 0 && target.size() > 4 && target.substr(target.size() - 4) == ".svg";
    EXPECT_NE(target[0], '/') << target;
    EXPECT_EQ(target.find("://"), std::string::npos) << target;
    EXPECT_TRUE(std::filesystem::is_regular_file(night.report.parent_path() / target)) << target;
  }
  EXPECT_GE(plots, 2u * 4u) << "pass_ms, mean_luminance, active_cells, lag, ... per scenario";
  EXPECT_GE(files, plots + 2u * 4u);  // + each thumbnail's full image
  EXPECT_NE(night.html.find("loading=\"lazy\""), std::string::npos);
}

// Numbers in the page's tables: for people, never an exponent (the frame
// time 12 580 ms, the relMSE 0.00001258).
TEST(ReportPage, TableNumbersHaveNoExponent) {
  test::TempDir dir("report-page-numbers");
  const Night night = write_night(dir, 2);
  const std::string text = page_text(night.html);
  const std::regex cell(R"re(<td>([\s\S]*?)</td>)re"), tag("<[^>]*>"), exponent(R"re(\d[eE][+-]?\d)re");
  std::size_t cells = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), cell); it != std::sregex_iterator(); ++it) {
    ++cells;
    const std::string shown = std::regex_replace((*it)[1].str(), tag, " ");
    EXPECT_FALSE(std::regex_search(shown, exponent)) << shown;
  }
  EXPECT_GT(cells, 20u);
  EXPECT_NE(text.find(">12" + kGroup + "580<"), std::string::npos) << "the overview's GPU ms/frame";
  EXPECT_NE(text.find("0.00001258"), std::string::npos) << "the reference check's relMSE";
}

// The speed-against-error scatter of many scenarios: inline in the page,
// each point's scenario its hover text (<title>), no name drawn on the plot,
// no script needed; the points also as a table.
TEST(ReportPage, ScatterNamesAreHoverTextNotLabelsThatPileUp) {
  ASSERT_TRUE(gnuplot_available()) << "install Debian's gnuplot-nox";
  test::TempDir dir("report-page-scatter");
  const Night night = write_night(dir, 8);
  const std::size_t heading = night.html.find("<h2>Speed against error</h2>");
  ASSERT_NE(heading, std::string::npos);
  const std::size_t begin = night.html.find("<svg", heading), end = night.html.find("</svg>", heading);
  ASSERT_NE(begin, std::string::npos) << "the scatter is inline";
  ASSERT_LT(begin, night.html.find("<h2>", heading + 1));
  const std::string svg = night.html.substr(begin, end - begin);
  EXPECT_EQ(svg.find("gnuplot_svg"), std::string::npos) << "no hook into a script the page does not have";
  const std::regex drawn(R"re(<text>([^<]*)</text>)re"), title(R"re(<title>([^<]*)</title>)re");
  std::set<std::string> hovered;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), drawn); it != std::sregex_iterator(); ++it)
    EXPECT_EQ((*it)[1].str().find("scenario_"), std::string::npos) << "a label drawn: " << (*it)[1];
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), title); it != std::sregex_iterator(); ++it)
    hovered.insert((*it)[1].str().substr(0, 11));
  for (int i = 0; i < 8; ++i) EXPECT_TRUE(hovered.count(fmt::format("scenario_{:02d}", i))) << i;
  EXPECT_NE(night.html.find("<table class=\"points\">"), std::string::npos);
}

}  // namespace
}  // namespace gi
