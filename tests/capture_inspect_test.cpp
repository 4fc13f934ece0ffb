// The capture inspector end to end: a small GI capture (32x18, Cornell box,
// 4 frames, frame 3 captured), read by the Python reader
// (python/giharness_capture.py, through tests/capture_reader_check.py) and
// made into a page by `giharness inspect`, which headless Chromium opens from
// disk (file://, no server) as tests/report_html_test.cpp does: no console
// error, every layer and buffer drawn, a pixel decoded to the very values
// of the .npy files, the comparison with a rerun, with a perturbed copy and
// with a baseline, the Embree reference beside the output, and a check's
// region carried from its result to the page's outline.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <regex>

#include "app/inspect_command.h"
#include "checks/check_result.h"
#include "core/exr_io.h"
#include "core/npy.h"
#include "replay/failure_capture.h"
#include "core/profile.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "core/scene_flatten.h"
#include "core/shared/world_cache.h"
#include "gpu/realtime_settings.h"
#include "tests/test_support.h"

namespace gi {
namespace {

constexpr std::uint32_t kWidth = 32, kHeight = 18;

std::filesystem::path make_capture(const std::filesystem::path& dir, const std::string& name,
                                   const std::string& frames = "3") {
  const std::filesystem::path scenario = dir / "gi_inspect.json";
  std::ofstream(scenario) << R"({"name": "gi_inspect", "scene": {"generator": "cornell_box"}, "resolution": [32, 18],
    "frames": 4, "seed": 5, "profile": "solari-0.18", "mode": "realtime", "gi": true, "events": [],
    "checks": [{"name": "finite"}]})";
  const test::CommandResult r =
      test::run_giharness("run " + scenario.string() + " --capture " + frames + " --out " + (dir / name).string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return dir / name / "captures/frame_00003";
}

// Debian's python3: the one .ci/setup gives python3-numpy (a python3 earlier
// on PATH, e.g. pyenv's, may lack numpy).
std::string python() { return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3"; }

test::CommandResult chromium(const std::filesystem::path& html, const std::string& fragment,
                             const std::filesystem::path& profile) {
  return test::run_command(
      "timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync --disable-dev-shm-usage "
      "--user-data-dir=" + profile.string() +
      " --enable-logging=stderr --v=0 --window-size=1280,2400 --virtual-time-budget=20000 --dump-dom 'file://" +
      html.string() + fragment + "'");
}

std::vector<std::string> console_errors(const std::string& log) {
  std::vector<std::string> errors;
  static const std::regex console(R"(:CONSOLE\(\d+\)\] "(.*))");
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (std::regex_search(line, console) || line.find("Uncaught") != std::string::npos) errors.push_back(line);
  return errors;
}

// The exact values the page decoded for (source, chain, field) at the picked pixel.
std::vector<double> page_values(const std::string& dom, const std::string& source, int chain, const std::string& field) {
  const std::regex row(fmt::format(R"re(<tr data-source="{}" data-chain="{}" data-field="{}" data-values="([^"]*)")re",
                                   std::regex_replace(source, std::regex(R"([.\[\]])"), R"(\$&)"), chain,
                                   std::regex_replace(field, std::regex(R"([.\[\]])"), R"(\$&)")));
  std::smatch m;
  std::vector<double> values;
  if (!std::regex_search(dom, m, row)) return values;
  std::istringstream in(m[1].str());
  for (std::string v; in >> v;) values.push_back(std::stod(v));
  return values;
}

float f32(const NpyArray& a, std::size_t word) {
  float f;
  std::memcpy(&f, a.data.data() + 4 * word, 4);
  return f;
}
std::uint32_t u32(const NpyArray& a, std::size_t word) {
  std::uint32_t u;
  std::memcpy(&u, a.data.data() + 4 * word, 4);
  return u;
}

bool chromium_installed() { return test::run_command("command -v chromium").exit_code == 0; }

TEST(CaptureReader, NamedFieldsEqualTheRawWordsAtTheStructsOffsets) {
  test::TempDir dir("capture-reader");
  const std::filesystem::path capture = make_capture(dir.path(), "run");
  const std::filesystem::path reader = std::filesystem::path(GIHARNESS_BINARY).parent_path() / "share/giharness/python";
  ASSERT_TRUE(std::filesystem::exists(reader / "giharness_capture.py")) << reader;
  const test::CommandResult r = test::run_command(python() + " " + (test::source_dir() / "tests/capture_reader_check.py").string() +
                                                  " " + reader.string() + " " + capture.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("equal their raw words"), std::string::npos) << r.output;
}

TEST(InspectPage, OpensInChromiumAndAClickedPixelShowsTheNpyValues) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("inspect-page");
  const std::filesystem::path capture = make_capture(dir.path(), "run");
  const std::filesystem::path page = dir.path() / "inspect.html";
  const test::CommandResult r = test::run_giharness("inspect " + capture.string() + " --out " + page.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // The pixel: the first, in scan order, whose DI reservoir has a W and whose GI reservoir holds a sample
  // whose cell the table holds (found here with the shared maths, as the
  // shader's query does: floor LOD at the camera, key, checksum, probing).
  const NpyArray di = read_npy(capture / "di.stored_reservoirs.npy");
  const NpyArray gi = read_npy(capture / "gi.stored_reservoirs.npy");
  const NpyArray checksums = read_npy(capture / "world_cache.checksums.npy");
  const NpyArray life = read_npy(capture / "world_cache.life.npy");
  const gpu::WorldCacheSettings s = world_cache_settings_from_profile(load_profile("solari-0.18"));
  const Scenario scenario = load_scenario(dir.path() / "gi_inspect.json");
  const glm::vec3 eye = glm::vec3(make_gpu_camera(build_scene(scenario).camera, kWidth, kHeight).position);
  const std::uint32_t cells = std::uint32_t(checksums.shape[0]);
  int px = -1, py = -1;
  std::uint32_t slot = 0;
  for (std::uint32_t i = 0; i < kWidth * kHeight && px < 0; ++i) {
    // A DI reservoir with a W too: a zero reads the same in any byte order.
    if (!(f32(gi, 12 * i + 11) > 0.0f) || !(f32(di, 8 * i + 5) > 0.0f)) continue;
    const glm::vec3 p(f32(gi, 12 * i), f32(gi, 12 * i + 1), f32(gi, 12 * i + 2));
    const glm::vec3 n(f32(gi, 12 * i + 4), f32(gi, 12 * i + 5), f32(gi, 12 * i + 6));
    const float size = shader::world_cache_cell_size(p, eye, s.cell_size_base, s.lod_scale);
    const auto qp = shader::world_cache_quantize_position(p, size);
    const auto qn = shader::world_cache_quantize_normal(n, s.normal_key_scale);
    const std::uint32_t sum = shader::world_cache_checksum(qp, qn);
    for (std::uint32_t step = 0, k = shader::world_cache_key(qp, qn, cells); step < s.max_probe_steps; ++step) {
      if (u32(checksums, k) == sum) {
        px = int(i % kWidth), py = int(i / kWidth), slot = k;
        break;
      }
      if (u32(checksums, k) == 0) break;
      k = shader::world_cache_next_key(k, cells, s.linear_probing);
    }
  }
  ASSERT_GE(px, 0) << "no GI sample of the capture has its cell in the table";
  const std::size_t pixel = std::size_t(py) * kWidth + px;

  const test::CommandResult dom = chromium(page, fmt::format("#all&pixel={},{}", px, py), dir.path() / "profile");
  EXPECT_TRUE(console_errors(dom.output).empty()) << dom.output.substr(0, 4000);
  ASSERT_NE(dom.output.find("data-ready=\"1\""), std::string::npos) << dom.output.substr(0, 4000);
  // Every layer and buffer drawn (the thumbnails of #all), and the preview <img> decoded.
  std::smatch drawn;
  ASSERT_TRUE(std::regex_search(dom.output, drawn, std::regex(R"re(data-drawn="(\d+)/(\d+)")re"))) << dom.output.substr(0, 2000);
  EXPECT_EQ(drawn[1].str(), drawn[2].str());
  EXPECT_GE(std::stoi(drawn[2].str()), 30);  // 10 layers, 24 buffers, 2 derived
  EXPECT_NE(dom.output.find("data-images-ok=\"1\""), std::string::npos);
  EXPECT_NE(dom.output.find("data-images-broken=\"0\""), std::string::npos);
  EXPECT_NE(dom.output.find(fmt::format("data-pixel=\"{},{}\"", px, py)), std::string::npos);
  // The picked pixel is ringed on the view.
  EXPECT_NE(dom.output.find(fmt::format("data-picked=\"{},{}\"", px, py)), std::string::npos);

  const std::vector<double> w = page_values(dom.output, "di/stored_reservoirs", 0, "unbiased_contribution_weight");
  const std::vector<double> m = page_values(dom.output, "di/stored_reservoirs", 0, "confidence_weight");
  ASSERT_EQ(w.size(), 1u) << dom.output.substr(0, 2000);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(w[0], double(f32(di, 8 * pixel + 5)));
  EXPECT_GT(w[0], 0.0);
  EXPECT_EQ(m[0], double(f32(di, 8 * pixel + 4)));
  const std::vector<double> sample = page_values(dom.output, "gi/stored_reservoirs", 0, "sample_position");
  ASSERT_EQ(sample.size(), 4u);
  for (int c = 0; c < 4; ++c) EXPECT_EQ(sample[c], double(f32(gi, 12 * pixel + c))) << c;
  const std::vector<double> cell_slot = page_values(dom.output, "derived/gi_sample_cache_cell", 0, "slot");
  const std::vector<double> cell_life = page_values(dom.output, "derived/gi_sample_cache_cell", 0, "life");
  ASSERT_EQ(cell_slot.size(), 1u);
  ASSERT_EQ(cell_life.size(), 1u);
  EXPECT_EQ(cell_slot[0], double(slot));
  EXPECT_EQ(cell_life[0], double(u32(life, slot)));
  EXPECT_GT(cell_life[0], 0.0);
}

TEST(InspectPage, AgainstARerunIsIdenticalAndAgainstAPerturbedCopyNamesBufferAndElement) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("inspect-diff");
  const std::filesystem::path capture = make_capture(dir.path(), "run");
  const std::filesystem::path rerun = make_capture(dir.path(), "rerun");
  const std::filesystem::path same = dir.path() / "same.html";
  ASSERT_EQ(test::run_giharness("inspect " + capture.string() + " --against " + rerun.string() + " --out " + same.string())
                .exit_code, 0);
  const test::CommandResult a = chromium(same, "", dir.path() / "profile-a");
  EXPECT_TRUE(console_errors(a.output).empty()) << a.output.substr(0, 4000);
  EXPECT_NE(a.output.find("data-identical=\"1\""), std::string::npos) << a.output.substr(0, 4000);
  EXPECT_NE(a.output.find(">identical: every buffer and every layer is equal bit for bit<"), std::string::npos);

  // One word changed: W of chain 0's DI reservoir at pixel (7, 5).
  const std::filesystem::path perturbed = dir.path() / "perturbed";
  std::filesystem::copy(capture, perturbed);
  NpyArray di = read_npy(perturbed / "di.stored_reservoirs.npy");
  const std::size_t word = 8 * (5 * kWidth + 7) + 5;
  const float changed = f32(di, word) + 1.0f;
  std::memcpy(di.data.data() + 4 * word, &changed, 4);
  write_npy(perturbed / "di.stored_reservoirs.npy", di.dtype, di.shape, di.data.data(), di.data.size());
  const std::filesystem::path diff = dir.path() / "diff.html";
  ASSERT_EQ(test::run_giharness("inspect " + capture.string() + " --against " + perturbed.string() + " --out " +
                                diff.string()).exit_code, 0);
  const test::CommandResult b = chromium(diff, "", dir.path() / "profile-b");
  EXPECT_TRUE(console_errors(b.output).empty()) << b.output.substr(0, 4000);
  EXPECT_NE(b.output.find("data-identical=\"0\""), std::string::npos);
  EXPECT_NE(b.output.find(">different: di/stored_reservoirs<"), std::string::npos) << b.output.substr(0, 4000);
  const std::regex row(R"re(<tr data-name="di/stored_reservoirs" data-status="different"><td>buffer</td><td>di/stored_reservoirs</td><td>different</td><td>1</td><td>576</td><td>\[0, 5, 7\] word 5 \(unbiased_contribution_weight\)</td>)re");
  EXPECT_TRUE(std::regex_search(b.output, row)) << b.output.substr(b.output.find("diff-table"), 3000);
}

// A replay (giharness replay, resumed from the snapshot of the frame before)
// captures the same frame again: the page holds the two identical, every
// buffer and layer bit for bit. A frame the replay does not run is bad input.
TEST(InspectPage, AgainstAReplayOfItselfIsIdentical) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("inspect-replay");
  // Frame 2's capture holds the state after frame 2: its replay runs frame 3 again.
  const std::filesystem::path capture = make_capture(dir.path(), "run", "2,3");
  const std::filesystem::path resumed = dir.path() / "run/captures/frame_00002";
  const test::CommandResult replay =
      test::run_giharness("replay " + resumed.string() + " --capture 3 --out " + (dir.path() / "replay").string());
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  const std::filesystem::path replayed = dir.path() / "replay/captures/frame_00003";
  ASSERT_TRUE(std::filesystem::exists(replayed / "manifest.json")) << replay.output;
  const std::filesystem::path page = dir.path() / "replay.html";
  ASSERT_EQ(test::run_giharness("inspect " + capture.string() + " --against " + replayed.string() + " --out " + page.string())
                .exit_code, 0);
  const test::CommandResult dom = chromium(page, "", dir.path() / "profile");
  EXPECT_TRUE(console_errors(dom.output).empty()) << dom.output.substr(0, 4000);
  EXPECT_NE(dom.output.find("data-identical=\"1\""), std::string::npos) << dom.output.substr(0, 4000);
  EXPECT_NE(dom.output.find(">identical: every buffer and every layer is equal bit for bit<"), std::string::npos);

  const test::CommandResult early =
      test::run_giharness("replay " + resumed.string() + " --capture 2 --out " + (dir.path() / "early").string());
  EXPECT_EQ(early.exit_code, 2) << early.output;
  EXPECT_NE(early.output.find("--capture"), std::string::npos) << early.output;
}

// The reference beside the output is `giharness reference`'s image of the same
// frame at the same spp (through the same cache), and a clicked pixel reads it.
TEST(InspectPage, TheReferenceBesideTheOutputIsTheReferenceCommandsImage) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("inspect-reference");
  const std::filesystem::path capture = make_capture(dir.path(), "run");
  const std::filesystem::path page = dir.path() / "inspect.html";
  const test::CommandResult r =
      test::run_giharness("inspect " + capture.string() + " --reference --reference-spp 8 --out " + page.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const test::CommandResult ref = test::run_giharness("reference " + (dir.path() / "gi_inspect.json").string() +
                                                      " --frame 3 --spp 8 --out " + (dir.path() / "ref").string());
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  EXPECT_NE(ref.output.find("(cached)"), std::string::npos) << "the inspector's reference is not the cache's: " << ref.output;
  const Image expected = read_exr(dir.path() / "ref/reference.exr").at("");
  const int px = 16, py = 9;
  const test::CommandResult dom = chromium(page, fmt::format("#pixel={},{}", px, py), dir.path() / "profile");
  EXPECT_TRUE(console_errors(dom.output).empty()) << dom.output.substr(0, 4000);
  ASSERT_NE(dom.output.find("data-ready=\"1\""), std::string::npos) << dom.output.substr(0, 4000);
  const std::vector<double> v = page_values(dom.output, "reference/output", 0, "rgb");
  ASSERT_EQ(v.size(), 3u) << dom.output.substr(0, 3000);
  const glm::vec3 e = expected.pixels[std::size_t(py) * kWidth + px];
  for (int c = 0; c < 3; ++c) EXPECT_EQ(v[c], double(e[c])) << c;
  EXPECT_GT(v[0] + v[1] + v[2], 0.0);
  // Both images beside each other, drawn.
  EXPECT_TRUE(std::regex_search(dom.output, std::regex(R"re(<canvas class="diff" data-source="output"[^>]*data-drawn="1")re")));
  EXPECT_TRUE(std::regex_search(dom.output, std::regex(R"re(<canvas class="diff" data-source="reference/output"[^>]*data-drawn="1")re")));
}

// A baseline as the nightly stores it (reports/baselines/<class>/<scenario>.json:
// the run's hashes, its final image beside), made from the capturing run.
std::filesystem::path make_baseline(const std::filesystem::path& run, const std::filesystem::path& dir,
                                    const std::string& changed_buffer = "") {
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(run / "summary.json"));
  nlohmann::json b = {{"scenario", "gi_inspect"}, {"hashes", summary["hashes"]}, {"image", "gi_inspect.exr"}};
  if (!changed_buffer.empty()) b["hashes"]["final_buffers"][changed_buffer] = "0123456789abcdef";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(run / summary["final_image"].get<std::string>(), dir / "gi_inspect.exr",
                             std::filesystem::copy_options::overwrite_existing);
  std::ofstream(dir / "gi_inspect.json") << b.dump(1);
  return dir / "gi_inspect.json";
}

TEST(InspectPage, AgainstABaselineOfTheSameRunIsIdenticalAndAChangedHashNamesTheBuffer) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("inspect-baseline");
  const std::filesystem::path capture = make_capture(dir.path(), "run");  // frame 3 of 4: the last
  const std::filesystem::path same = make_baseline(dir.path() / "run", dir.path() / "same");
  const std::filesystem::path page = dir.path() / "same.html";
  ASSERT_EQ(test::run_giharness("inspect " + capture.string() + " --against " + same.string() + " --out " + page.string())
                .exit_code, 0);
  const test::CommandResult a = chromium(page, "", dir.path() / "profile-a");
  EXPECT_TRUE(console_errors(a.output).empty()) << a.output.substr(0, 4000);
  EXPECT_NE(a.output.find("data-identical=\"1\""), std::string::npos) << a.output.substr(a.output.find("id=\"diff\""), 3000);
  EXPECT_NE(a.output.find(">identical: every buffer's hash equals the baseline's, and the output its final image<"),
            std::string::npos);
  EXPECT_NE(a.output.find("<tr data-name=\"output\" data-status=\"equal\"><td>layer</td>"), std::string::npos);

  const std::filesystem::path changed = make_baseline(dir.path() / "run", dir.path() / "changed", "gi/stored_reservoirs");
  const std::filesystem::path diff = dir.path() / "changed.html";
  ASSERT_EQ(test::run_giharness("inspect " + capture.string() + " --against " + changed.string() + " --out " + diff.string())
                .exit_code, 0);
  const test::CommandResult b = chromium(diff, "", dir.path() / "profile-b");
  EXPECT_TRUE(console_errors(b.output).empty()) << b.output.substr(0, 4000);
  EXPECT_NE(b.output.find("data-identical=\"0\""), std::string::npos);
  EXPECT_NE(b.output.find(">different: gi/stored_reservoirs<"), std::string::npos) << b.output.substr(b.output.find("id=\"diff\""), 3000);
  EXPECT_NE(b.output.find("<tr data-name=\"gi/stored_reservoirs\" data-status=\"different\">"), std::string::npos);
  EXPECT_NE(b.output.find("<td>0123456789abcdef</td>"), std::string::npos);

  // A baseline without hashes: exit 2, naming the file and the JSON path.
  std::ofstream(dir.path() / "bad.json") << R"({"scenario": "gi_inspect", "image": "gi_inspect.exr"})";
  const test::CommandResult bad = test::run_giharness("inspect " + capture.string() + " --against " +
                                                      (dir.path() / "bad.json").string() + " --out " + (dir.path() / "bad.html").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("bad.json: /hashes/final_buffers"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "bad.html"));
}

// A check's region goes from its result (CheckResult::region, region_mask) to
// the failure capture's entry the nightly reads, and the page outlines both.
TEST(InspectPage, ACheckRegionReachesTheFailureCaptureAndThePageOutlinesIt) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("inspect-region");
  const std::filesystem::path capture = make_capture(dir.path(), "run");
  // A mask: the rectangle x 4..9, y 2..6.
  std::vector<bool> mask(kWidth * kHeight, false);
  Image mask_image(kWidth, kHeight);
  for (std::uint32_t y = 2; y <= 6; ++y)
    for (std::uint32_t x = 4; x <= 9; ++x) mask[y * kWidth + x] = true, mask_image.pixels[y * kWidth + x] = glm::vec3(1.0f);
  EXPECT_EQ(mask_bounds(mask, kWidth), nlohmann::json({4, 2, 9, 6}));
  EXPECT_TRUE(mask_bounds(std::vector<bool>(kWidth * kHeight, false), kWidth).is_null());
  write_exr(dir.path() / "run/region/frame_00003.exr", {{"shadowed_region", &mask_image}});

  CheckResult failed;
  failed.name = "light_leak";
  failed.verdict = Verdict::fail;
  failed.first_failing_frame = 3;
  failed.region = mask_bounds(mask, kWidth);
  failed.region_mask = {{"file", "region/frame_00003.exr"}, {"layer", "shadowed_region"}};
  EXPECT_EQ(failed.to_json()["region"], nlohmann::json({4, 2, 9, 6}));
  std::vector<CheckResult> checks{failed};
  RunOptions run;
  run.out_dir = dir.path() / "run";
  // Frame 3 is captured already: nothing is rerun.
  const nlohmann::json list = capture_failing_frames(Scenario{}, run, 4, {3}, checks);
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0]["region"], nlohmann::json({4, 2, 9, 6}));
  EXPECT_EQ(list[0]["region_mask"]["layer"], "shadowed_region");

  // What the nightly hands the page (app/nightly.cpp).
  InspectExtras extras;
  extras.region = list[0]["region"];
  extras.region_mask_file = run.out_dir / list[0]["region_mask"]["file"].get<std::string>();
  extras.region_mask_layer = list[0]["region_mask"]["layer"];
  const std::filesystem::path page = dir.path() / "region.html";
  write_inspect_page(capture, extras, page);
  const test::CommandResult dom = chromium(page, "#source=output", dir.path() / "profile");
  EXPECT_TRUE(console_errors(dom.output).empty()) << dom.output.substr(0, 4000);
  ASSERT_NE(dom.output.find("data-ready=\"1\""), std::string::npos) << dom.output.substr(0, 4000);
  EXPECT_NE(dom.output.find("data-region=\"4,2,9,6\""), std::string::npos) << dom.output.substr(0, 2000);
  // The mask's border: the rectangle's 6x5 less its 4x3 inside.
  EXPECT_NE(dom.output.find("data-region-mask=\"18\""), std::string::npos) << dom.output.substr(0, 2000);
  // The nightly report's link names the same region in the fragment: the
  // mask is still drawn; a fragment naming another region outlines that alone.
  const test::CommandResult linked = chromium(page, "#source=output&region=4,2,9,6", dir.path() / "profile2");
  EXPECT_NE(linked.output.find("data-region-mask=\"18\""), std::string::npos) << linked.output.substr(0, 2000);
  const test::CommandResult other = chromium(page, "#source=output&region=1,1,3,3", dir.path() / "profile3");
  EXPECT_NE(other.output.find("data-region=\"1,1,3,3\""), std::string::npos) << other.output.substr(0, 2000);
  EXPECT_EQ(other.output.find("data-region-mask="), std::string::npos) << other.output.substr(0, 2000);
}

// The world cache as a picture: every live cell in front of the camera lands
// on the image, and a pixel holds the slot and life of a cell drawn there.
TEST(InspectPage, TheProjectedCacheCellsAreTheTablesLiveCells) {
  ASSERT_TRUE(chromium_installed()) << "install Debian's chromium (.ci/setup)";
  test::TempDir dir("inspect-cells");
  const std::filesystem::path capture = make_capture(dir.path(), "run");
  const std::filesystem::path page = dir.path() / "inspect.html";
  ASSERT_EQ(test::run_giharness("inspect " + capture.string() + " --out " + page.string()).exit_code, 0);
  const NpyArray life = read_npy(capture / "world_cache.life.npy");
  // A pixel the G-buffer covers, in the middle of the box's back wall.
  const int px = 16, py = 9;
  const test::CommandResult dom = chromium(page, fmt::format("#source=derived/cache_cells_projected&pixel={},{}", px, py),
                                           dir.path() / "profile");
  EXPECT_TRUE(console_errors(dom.output).empty()) << dom.output.substr(0, 4000);
  ASSERT_NE(dom.output.find("data-ready=\"1\""), std::string::npos) << dom.output.substr(0, 4000);
  const std::vector<double> slot = page_values(dom.output, "derived/cache_cells_projected", 0, "slot");
  const std::vector<double> l = page_values(dom.output, "derived/cache_cells_projected", 0, "life");
  ASSERT_EQ(slot.size(), 1u) << dom.output.substr(0, 3000);
  ASSERT_LT(slot[0], double(life.shape[0])) << "no live cell drawn at the back wall";
  EXPECT_EQ(l[0], double(u32(life, std::size_t(slot[0]))));
  EXPECT_GT(l[0], 0.0);
  EXPECT_NE(dom.output.find("cells drawn"), std::string::npos);
}

}  // namespace
}  // namespace gi
