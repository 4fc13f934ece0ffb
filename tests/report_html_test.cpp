// The nightly's HTML report in a real browser: Debian's chromium, headless,
// loads report.html from its folder on disk (file://, no server; thumbnails
// embedded, plots and full images as files beside the page). Passes when the
// console shows no error, every image (plots, thumbnails) decoded, also the
// lazily loaded ones (report.html#all loads them at once), and the
// screenshot is not blank.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb/stb_image.h>

#include "tests/test_support.h"

namespace gi {
namespace {

// One headless Chromium run; `mode` is e.g. "--dump-dom" or "--screenshot=F".
test::CommandResult chromium(const std::filesystem::path& html, const std::string& mode, const test::TempDir& profile,
                             const std::string& fragment = "") {
  return test::run_command(
      "timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync --disable-dev-shm-usage "
      "--user-data-dir=" + (profile.path() / "profile").string() +
      " --enable-logging=stderr --v=0 --window-size=1280,2400 --virtual-time-budget=5000 " + mode + " 'file://" +
      html.string() + fragment + "'");
}

// Console messages Chromium logs at error level, and uncaught exceptions.
std::vector<std::string> console_errors(const std::string& log) {
  std::vector<std::string> errors;
  static const std::regex console(R"(:CONSOLE\(\d+\)\] "(.*))");
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, console) || line.find("Uncaught") != std::string::npos) errors.push_back(line);
  }
  return errors;
}

bool chromium_installed() { return test::run_command("command -v chromium").exit_code == 0; }

// Fraction of pixels that are not near-white, and how many distinct colours.
std::pair<double, std::size_t> ink(const std::filesystem::path& png) {
  int w = 0, h = 0, c = 0;
  unsigned char* data = stbi_load(png.c_str(), &w, &h, &c, 3);
  if (!data) return {0.0, 0};
  std::size_t inked = 0;
  std::set<unsigned> colours;
  for (int i = 0; i < w * h; ++i) {
    const unsigned char* p = data + 3 * i;
    if (p[0] < 235 || p[1] < 235 || p[2] < 235) ++inked;
    colours.insert((unsigned(p[0]) << 16) | (unsigned(p[1]) << 8) | p[2]);
  }
  stbi_image_free(data);
  return {double(inked) / double(w * h), colours.size()};
}

// The detector itself: a page with a script error and a broken image is
// caught (so a clean report is clean, not unobserved).
TEST(ReportHtml, ChromiumConsoleErrorsAreDetected) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("report-html-bad");
  const std::filesystem::path html = dir.path() / "bad.html";
  std::ofstream(html) << "<!DOCTYPE html><html><body><img alt=\"x\" src=\"data:image/png;base64,AAAA\">"
                         "<script>no_such_function();</script></body></html>";
  const test::CommandResult r = chromium(html, "--dump-dom", dir);
  EXPECT_FALSE(console_errors(r.output).empty()) << r.output;
}

TEST(ReportHtml, NightlyReportOpensInHeadlessChromiumWithPlotsAndImages) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("report-html");
  const std::filesystem::path suite = dir.path() / "suite", out = dir.path() / "out", base = dir.path() / "base";
  std::filesystem::create_directories(suite);
  const std::filesystem::path scenario = suite / "tiny_cornell.json";
  std::filesystem::copy(test::source_dir() / "tests/data/suites/tiny/tiny_cornell.json", suite);
  // A baseline, then the light 0.2 % dimmer: the report also shows a change
  // (baseline, current and difference images).
  const test::CommandResult first = test::run_giharness("nightly --suite " + suite.string() + " --out " +
                                                        (dir.path() / "first").string() + " --baseline " +
                                                        base.string() + " --update-baseline");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  for (const auto& entry : std::filesystem::directory_iterator(base))
    std::ofstream(entry.path() / "tolerances.json") << R"([{"pattern": "timings/*", "kind": "ignore"}])";
  nlohmann::json doc = test::read_json(scenario);
  doc["scene"]["params"]["light_scale"] = 0.998;
  std::ofstream(scenario) << doc.dump(2);
  const test::CommandResult run = test::run_giharness("nightly --suite " + suite.string() + " --out " + out.string() +
                                                      " --baseline " + base.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_EQ(test::read_json(out / "summary.json")["changes"]["changed"], 1) << run.output;
  const std::filesystem::path html = out / "report.html";
  std::ifstream in(html);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  // Offline from the folder: nothing from a network, every file it loads
  // beside it (plots/*.svg), thumbnails embedded.
  EXPECT_EQ(text.find("src=\"http"), std::string::npos);
  EXPECT_EQ(text.find("<link"), std::string::npos);
  std::size_t plots = 0, previews = 0;
  const std::regex plot_src(R"re(<img class="plot" loading="lazy"[^>]* src="(plots/[^"]+\.svg)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), plot_src); it != std::sregex_iterator(); ++it) {
    ++plots;
    EXPECT_TRUE(std::filesystem::is_regular_file(out / (*it)[1].str())) << (*it)[1];
  }
  const std::regex thumbnail(R"re(<a href="([^"]+)"><img class="thumb"[^>]* src="data:image/(png|jpeg);base64,)re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), thumbnail); it != std::sregex_iterator(); ++it) {
    ++previews;
    EXPECT_TRUE(std::filesystem::is_regular_file(out / (*it)[1].str())) << "full image " << (*it)[1];
  }
  EXPECT_EQ(text.find("data:image/svg"), std::string::npos) << "plots are files, not in the page";
  // mean_luminance, nonfinite_*, window_*, pass_ms, the reference check's error (speed vs error: inline).
  EXPECT_GE(plots, 5u);
  EXPECT_GE(previews, 7u);  // gpu, embree, error map + the capture + baseline, current, difference
  EXPECT_NE(text.find("reference/frame_00007.exr"), std::string::npos);
  EXPECT_NE(text.find("<figure class=\"plot\" role=\"img\" aria-label=\"speed against error\"><svg"), std::string::npos);

  const test::CommandResult dom = chromium(html, "--dump-dom", dir, "#all");
  EXPECT_TRUE(console_errors(dom.output).empty()) << dom.output;
  std::smatch m;
  const std::regex counts(R"re(data-images-ok="(\d+)" data-images-broken="(\d+)")re");
  ASSERT_TRUE(std::regex_search(dom.output, m, counts))
      << dom.output.substr(0, 4000);
  EXPECT_EQ(std::stoul(m[1].str()), plots + previews);
  EXPECT_EQ(m[2].str(), "0");
  EXPECT_NE(dom.output.find("data-images-deferred=\"0\""), std::string::npos);

  const std::filesystem::path png = dir.path() / "screenshot.png";
  const test::CommandResult shot = chromium(html, "--screenshot=" + png.string(), dir);
  EXPECT_TRUE(console_errors(shot.output).empty()) << shot.output;
  ASSERT_TRUE(std::filesystem::exists(png)) << shot.output;
  const auto [inked, colours] = ink(png);
  EXPECT_GT(inked, 0.03) << "screenshot nearly blank";
  EXPECT_GT(colours, 64u) << "screenshot has almost no colours: no images drawn";
}

// The speed-against-error plot shows realtime scenarios: a suite
// of a reference-mode and a realtime GI scenario; the plot's SVG names both
// and the path tracers measured at the realtime one's time, the equal-time
// table has its row, and the page opens in Chromium with every image decoded.
TEST(ReportHtml, SpeedAgainstErrorPlotShowsRealtimeScenariosAndTheirEqualTimePeers) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("report-html-speed");
  const std::filesystem::path suite = dir.path() / "suite", out = dir.path() / "out";
  std::filesystem::create_directories(suite);
  std::filesystem::copy(test::source_dir() / "tests/data/suites/tiny/tiny_cornell.json", suite);
  std::filesystem::copy(test::source_dir() / "tests/data/suites/realtime/rt_cornell_gi.json", suite);
  const test::CommandResult run = test::run_giharness("nightly --suite " + suite.string() + " --out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::filesystem::path html = out / "report.html";
  std::ifstream in(html);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  // Inline, so that each point's hover text (its <title>) shows: the
  // scenarios are named there, never drawn as labels that pile up.
  const std::string marker = "aria-label=\"speed against error\"><svg";
  const std::size_t at = text.find(marker);
  ASSERT_NE(at, std::string::npos);
  const std::string svg = text.substr(at, text.find("</svg>", at) - at);
  for (const char* expected : {"realtime (one frame)", "<title>rt_cornell_gi: ", "reference mode (accumulated image)",
                               "<title>tiny_cornell: ", "GPU path tracer at a realtime scene", "Embree at a realtime scene",
                               "<title>rt_cornell_gi ("})  // a path tracer's point, at the realtime scene
    EXPECT_NE(svg.find(expected), std::string::npos) << expected;
  EXPECT_EQ(svg.find("<text>tiny_cornell"), std::string::npos);
  EXPECT_EQ(svg.find("gnuplot_svg"), std::string::npos);
  EXPECT_NE(text.find("At equal time, same device"), std::string::npos);
  EXPECT_NE(text.find("Per signal"), std::string::npos);

  const test::CommandResult dom = chromium(html, "--dump-dom", dir);
  EXPECT_TRUE(console_errors(dom.output).empty()) << dom.output;
  std::smatch m;
  const std::regex counts(R"re(data-images-ok="(\d+)" data-images-broken="(\d+)")re");
  ASSERT_TRUE(std::regex_search(dom.output, m, counts)) << dom.output.substr(0, 4000);
  EXPECT_GT(std::stoul(m[1].str()), 0u);
  EXPECT_EQ(m[2].str(), "0");
  // The equal-time table as the browser laid it out: the realtime scenario's row.
  EXPECT_NE(dom.output.find("<td>rt_cornell_gi</td>"), std::string::npos);
}

}  // namespace
}  // namespace gi
