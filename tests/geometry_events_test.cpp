// Geometry events (spawn, despawn, transform) keep the pipeline's state, as
// Bevy's Solari does ("spawning cliffs" must not reset it): only acceleration
// structures and scene buffers change (Renderer::update_geometry). End to end
// on lavapipe with ReSTIR GI querying the world cache ("gi": true).
//
// - Geometry nothing can see (outside a closed room) leaves every state
//   buffer, in every frame, bit-identical to the run without it, on both
//   tracing backends; replays across and after the spawn stay bit-exact.
// - Geometry the camera sees: the cache cells out of its reach keep their
//   bits (checksum, life, radiance, geometry) across the spawn frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <tuple>

#include <glm/glm.hpp>

#include "core/npy.h"
#include "tests/test_support.h"

namespace gi {
namespace {

using nlohmann::json;

std::filesystem::path write_scenario(const std::filesystem::path& dir, const std::string& name, const json& scene,
                                     const json& camera, const json& events, std::uint32_t frames,
                                     std::vector<std::uint32_t> resolution) {
  json doc = {{"name", name},          {"scene", scene},   {"resolution", resolution}, {"frames", frames},
              {"seed", 3},             {"profile", "solari-0.18"}, {"mode", "realtime"}, {"gi", true},
              {"events", events},      {"checks", json::array({json{{"name", "finite"}}})}};
  if (!camera.is_null()) doc["camera"] = camera;
  const std::filesystem::path file = dir / (name + ".json");
  std::ofstream(file) << doc.dump(1);
  return file;
}

std::vector<json> read_lines(const std::filesystem::path& file) {
  std::vector<json> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(json::parse(line));
  return lines;
}

// The pipeline's state of one hash record: every buffer but the realtime
// reference check's per-window sums (*/accumulation), which restart at any
// event by design (the check's static window, README "realtime reference").
json pipeline_state(const json& record) {
  json out = json::array();
  for (const json& b : record["buffers"]) {
    const std::string name = b[0];
    if (!name.ends_with("/accumulation")) out.push_back(b);
  }
  return out;
}

// The buffers whose hashes differ between two records of one frame.
std::string differing_buffers(const json& a, const json& b) {
  std::string out;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    if (a[i] != b[i]) out += a[i][0].get<std::string>() + " ";
  return out;
}

// A captured buffer by its state name ("world_cache/checksums").
NpyArray captured(const std::filesystem::path& capture, const std::string& buffer) {
  const json manifest = test::read_json(capture / "manifest.json");
  for (const json& b : manifest["buffers"])
    if (b["name"] == buffer) return read_npy(capture / b["file"].get<std::string>());
  ADD_FAILURE() << capture << " has no buffer " << buffer;
  return {};
}

template <class T>
T word(const NpyArray& a, std::size_t index) {
  T v;
  std::memcpy(&v, a.data.data() + 4 * index, 4);
  return v;
}

// Mean confidence M over a reservoir buffer: `stride` words a reservoir, M at `offset`.
double mean_confidence(const NpyArray& a, std::size_t stride, std::size_t offset) {
  const std::size_t n = a.data.size() / 4 / stride;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += word<float>(a, i * stride + offset);
  return sum / double(n);
}

test::CommandResult run(const std::filesystem::path& scenario, const std::filesystem::path& out,
                        const std::string& args, const std::string& env = "") {
  return test::run_giharness("run " + scenario.string() + " --set world_cache.cells=65536 " + args + " --out " +
                                 out.string(),
                             env);
}

// The closed room (nothing leaves it, nothing outside is seen) with a block
// copied outside and a generated cliff behind the front wall at frame 5,
// both moved and one despawned at frame 7.
class HiddenGeometry : public ::testing::TestWithParam<std::string> {};

TEST_P(HiddenGeometry, EveryStateBufferMatchesTheRunWithoutTheEvents) {
  const std::string backend = GetParam();
  if (backend == "rayquery") GI_SKIP_WITHOUT_RAY_QUERY();
  test::TempDir dir("geometry_hidden_" + backend);
  const json scene = {{"generator", "cache_closed_room"}};
  const json events = json::array(
      {json{{"type", "spawn"}, {"frame", 5}, {"instance", "block_outside"}, {"of", "red_block"},
            {"translation", {8, 0, 0}}},
       json{{"type", "spawn"},
            {"frame", 5},
            {"instance", "cliff_outside"},
            {"mesh", {{"generator", "cliff"}, {"params", {{"triangles", 2000}, {"width", 4}, {"height", 2}, {"depth", 2}}}}},
            {"translation", {0, 0, 10}}},
       json{{"type", "transform"}, {"frame", 7}, {"instance", "cliff_outside"}, {"translation", {1, 0, 2}}},
       json{{"type", "despawn"}, {"frame", 7}, {"instance", "block_outside"}}});
  const std::uint32_t frames = 10;
  const auto without = write_scenario(dir.path(), "without", scene, nullptr, json::array(), frames, {48, 27});
  const auto with = write_scenario(dir.path(), "with", scene, nullptr, events, frames, {48, 27});
  const std::string args = "--backend " + backend + " --capture 0,4,5,6";
  const auto a = dir.path() / "a", b = dir.path() / "b";
  test::CommandResult r = run(without, a, args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run(with, b, args);
  ASSERT_EQ(r.exit_code, 0) << r.output;

  // Every state buffer of every frame, the spawn frame and after included.
  const auto log_a = read_lines(a / "buffer_hashes.jsonl"), log_b = read_lines(b / "buffer_hashes.jsonl");
  ASSERT_EQ(log_a.size(), frames);
  ASSERT_EQ(log_b.size(), frames);
  for (std::uint32_t f = 0; f < frames; ++f) {
    const json state_a = pipeline_state(log_a[f]), state_b = pipeline_state(log_b[f]);
    ASSERT_GT(state_a.size(), 15u);
    EXPECT_TRUE(state_a == state_b) << "frame " << f << " differs in: " << differing_buffers(state_a, state_b);
  }

  // The comparison means something: the cache holds cells and changes over
  // the spawn frame, and the reservoirs carry history (M above a first frame's).
  const auto a0 = a / "captures/frame_00000", a5 = a / "captures/frame_00005", b5 = b / "captures/frame_00005";
  const NpyArray checksums = captured(b5, "world_cache/checksums");
  std::size_t cells = 0;
  for (std::size_t i = 0; i < checksums.element_count(); ++i) cells += word<std::uint32_t>(checksums, i) != 0;
  EXPECT_GT(cells, 50u);
  EXPECT_NE(log_a[4]["buffers"], log_a[5]["buffers"]);
  // DiReservoir: light (4 words), M, W, pad, pad. GiReservoir: position.xyz, M, ...
  const double di_m0 = mean_confidence(captured(a0, "di/stored_reservoirs"), 8, 4);
  const double di_m5 = mean_confidence(captured(b5, "di/stored_reservoirs"), 8, 4);
  const double gi_m0 = mean_confidence(captured(a0, "gi/stored_reservoirs"), 12, 3);
  const double gi_m5 = mean_confidence(captured(b5, "gi/stored_reservoirs"), 12, 3);
  EXPECT_EQ(di_m5, mean_confidence(captured(a5, "di/stored_reservoirs"), 8, 4));
  EXPECT_GT(di_m5, 2.0 * di_m0) << "DI reservoirs lost their history at the spawn";
  EXPECT_GT(gi_m5, 2.0 * gi_m0) << "GI reservoirs lost their history at the spawn";
  // The passes' host state after the spawn frame: history valid.
  const json manifest = test::read_json(b5 / "manifest.json");
  for (const json& e : manifest["host_state"]) {
    if (e["name"] == "di/flags") {
      EXPECT_EQ(e["words"][1], 1u);
    }
    if (e["name"] == "gi/flags") {
      EXPECT_EQ(e["words"][0], 1u);
    }
  }

  // Replays stay bit-exact: from before the spawn (the replay applies it) and
  // from after it (the pipeline is built with the spawned geometry).
  for (const char* capture : {"frame_00004", "frame_00006"}) {
    const auto out = dir.path() / (std::string("replay_") + capture);
    r = test::run_giharness("replay " + (b / "captures" / capture).string() + " --verify --out " + out.string());
    EXPECT_EQ(r.exit_code, 0) << capture << ": " << r.output;
    EXPECT_EQ(test::read_json(out / "verify.json")["verdict"], "identical") << capture;
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, HiddenGeometry, ::testing::Values("bvh", "rayquery"),
                         [](const auto& info) { return info.param; });

// Same bits at any lavapipe thread count across spawns of both kinds.
TEST(GeometryEvents, SpawnRunIsBitIdenticalAtOneThread) {
  test::TempDir dir("geometry_threads");
  const json events = json::array(
      {json{{"type", "spawn"}, {"frame", 3}, {"instance", "block_2"}, {"of", "green_block"},
            {"translation", {-1.2, 0, 1.0}}},
       json{{"type", "spawn"},
            {"frame", 4},
            {"instance", "rock"},
            {"mesh", {{"generator", "cliff"}, {"params", {{"triangles", 500}, {"width", 0.6}, {"height", 0.5}, {"depth", 0.4}}}}},
            {"translation", {-1.2, 0, 0.2}}}});
  const auto s = write_scenario(dir.path(), "visible_spawns", {{"generator", "cache_closed_room"}}, nullptr, events, 8,
                                {48, 27});
  ASSERT_EQ(run(s, dir.path() / "default", "--capture 5 --hash-log").exit_code, 0);
  ASSERT_EQ(run(s, dir.path() / "one", "--capture 5 --hash-log", "LP_NUM_THREADS=1").exit_code, 0);
  const auto log = read_lines(dir.path() / "default/buffer_hashes.jsonl");
  ASSERT_EQ(log.size(), 8u);
  EXPECT_EQ(log, read_lines(dir.path() / "one/buffer_hashes.jsonl"));
}

// The room and the sunlit yard, seen from inside the room through the doorway;
// a cliff spawned at the yard's far end (about 56 m away) at frame 6. GI and
// cache rays reach 50 m (world_cache.gi_ray_tmax), so cells more than 51 m
// from the cliff's box cannot see it: they keep their bits across the spawn
// frame, slot by slot, against the run without the spawn.
TEST(GeometryEvents, CellsOutOfTheSpawnsReachKeepTheirBitsAcrossTheSpawnFrame) {
  test::TempDir dir("geometry_visible");
  const json scene = {{"generator", "cache_room_and_yard"}};
  const json camera = {{"position", {0.0, 1.6, -1.0}}, {"target", {0.0, 1.4, 20.0}}, {"fov_y_degrees", 70}};
  const std::uint32_t spawn = 6, frames = 8;
  const json events = json::array({json{
      {"type", "spawn"},
      {"frame", spawn},
      {"instance", "far_cliff"},
      {"mesh", {{"generator", "cliff"}, {"params", {{"triangles", 2000}, {"width", 12}, {"height", 6}, {"depth", 3}}}}},
      {"translation", {0, 0, 58}}}});
  const auto without = write_scenario(dir.path(), "without", scene, camera, json::array(), frames, {96, 54});
  const auto with = write_scenario(dir.path(), "with", scene, camera, events, frames, {96, 54});
  const std::string args = "--capture " + std::to_string(spawn);
  ASSERT_EQ(run(without, dir.path() / "a", args).exit_code, 0);
  ASSERT_EQ(run(with, dir.path() / "b", args).exit_code, 0);
  const auto a = dir.path() / "a/captures/frame_00006", b = dir.path() / "b/captures/frame_00006";

  // The cliff's box: x ±6, y 0..6, z 58 ± 1.5, padded by 1 m for the carving.
  const glm::vec3 lo(-7.0f, -1.0f, 55.5f), hi(7.0f, 7.0f, 60.5f);
  auto distance = [&](glm::vec3 p) { return glm::length(glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f))); };
  const NpyArray sum_a = captured(a, "world_cache/checksums"), sum_b = captured(b, "world_cache/checksums");
  const NpyArray life_a = captured(a, "world_cache/life"), life_b = captured(b, "world_cache/life");
  const NpyArray rad_a = captured(a, "world_cache/radiance"), rad_b = captured(b, "world_cache/radiance");
  const NpyArray geo_a = captured(a, "world_cache/geometry"), geo_b = captured(b, "world_cache/geometry");
  std::size_t far = 0, far_kept = 0, near_new = 0;
  for (std::size_t i = 0; i < sum_a.element_count(); ++i) {
    const std::uint32_t ca = word<std::uint32_t>(sum_a, i), cb = word<std::uint32_t>(sum_b, i);
    // WorldCacheGeometry: position (vec4), normal (vec4).
    if (cb != 0 && ca == 0) {
      const glm::vec3 p(word<float>(geo_b, 8 * i), word<float>(geo_b, 8 * i + 1), word<float>(geo_b, 8 * i + 2));
      near_new += distance(p) < 10.0f;
    }
    if (ca == 0) continue;
    const glm::vec3 p(word<float>(geo_a, 8 * i), word<float>(geo_a, 8 * i + 1), word<float>(geo_a, 8 * i + 2));
    if (distance(p) <= 51.0f) continue;
    ++far;
    const bool kept = cb == ca && word<std::uint32_t>(life_a, i) == word<std::uint32_t>(life_b, i) &&
                      std::memcmp(rad_a.data.data() + 16 * i, rad_b.data.data() + 16 * i, 16) == 0 &&
                      std::memcmp(geo_a.data.data() + 32 * i, geo_b.data.data() + 32 * i, 32) == 0;
    far_kept += kept;
  }
  std::cout << far << " cells out of the cliff's reach, " << far_kept << " kept their bits; " << near_new
            << " new cells near it\n";
  EXPECT_GT(far, 200u);
  EXPECT_EQ(far_kept, far);
  EXPECT_GT(near_new, 0u) << "the cliff should be seen (cells inserted near it)";

  // The reservoirs keep their history: pixels left untouched by the cliff
  // hold the same reservoirs as without it, and the mean confidence stays.
  for (const auto& [buffer, stride, m] : {std::tuple{"di/stored_reservoirs", 8, 4}, {"gi/stored_reservoirs", 12, 3}}) {
    const NpyArray ra = captured(a, buffer), rb = captured(b, buffer);
    ASSERT_EQ(ra.data.size(), rb.data.size());
    const std::size_t n = ra.data.size() / (4 * stride);
    std::size_t same = 0;
    for (std::size_t i = 0; i < n; ++i)
      same += std::memcmp(ra.data.data() + 4 * stride * i, rb.data.data() + 4 * stride * i, 4 * stride) == 0;
    const double ma = mean_confidence(ra, stride, m), mb = mean_confidence(rb, stride, m);
    std::cout << buffer << ": " << same << " of " << n << " identical; mean M " << mb << " (without the spawn " << ma
              << ")\n";
    EXPECT_GT(same, n * 3 / 4) << buffer;
    EXPECT_NEAR(mb, ma, 0.05 * ma) << buffer;
  }
}

}  // namespace
}  // namespace gi
