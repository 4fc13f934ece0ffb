// The cache_lifetime and blend_lag checks: their judgement on hand-made
// curves and statistics (each failure fires on the bug it exists for), then
// the four verdicts on the issue-4 scenarios — 0.18 passes both checks, 0.17's
// lifetime rule fails cache_lifetime, 0.17's fixed blend fails blend_lag.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/scenario.h"
#include "checks/blend_lag_check.h"
#include "checks/cache_lifetime_check.h"
#include "replay/run_scenario.h"
#include "tests/test_support.h"

namespace gi {
namespace {

// A level that steps at `event` from `before` to `after`, approaching it by
// `keep` per frame (0: at once).
std::vector<double> step_curve(std::size_t frames, std::size_t event, double before, double after, double keep) {
  std::vector<double> v(frames, before);
  double x = before;
  for (std::size_t t = event; t < frames; ++t) {
    x = after + (x - after) * keep;
    v[t] = x;
  }
  return v;
}

TEST(BlendLagJudge, FastSettlingPasses) {
  BlendLagParams p;  // ε 5 %, δ 2 %, limit 10, 8 steady frames
  // Settles within 2 frames: 0.2² · 100 = 4 < 5 % of 100.
  const CheckResult r = judge_blend_lag(p, {40}, {{"output_luminance", step_curve(80, 40, 100.0, 0.0, 0.2)}});
  EXPECT_EQ(r.verdict, Verdict::pass) << r.message;
  EXPECT_EQ(r.figures["max_lag_frames"], 1);
}

TEST(BlendLagJudge, SlowExponentialFailsWithLagInFrames) {
  BlendLagParams p;
  // 0.17's fixed blend: 1/20 of each new sample, so the old level keeps 0.95
  // per frame. The window's last 8 frames average 0.5, the band is ±5 around
  // it: 100 · 0.95^n ≤ 5.5 from n = 57, i.e. frame 66, a lag of 56 frames.
  const CheckResult r = judge_blend_lag(p, {10}, {{"output_luminance", step_curve(120, 10, 100.0, 0.0, 0.95)}});
  EXPECT_EQ(r.verdict, Verdict::fail);
  EXPECT_NE(r.message.find("lag 56 frames after the event at frame 10"), std::string::npos) << r.message;
  EXPECT_EQ(r.first_failing_frame, 21u);  // event + limit + 1
}

TEST(BlendLagJudge, NotSettledWithinTheWindowFails) {
  BlendLagParams p;
  // Still falling 10 % a frame at the end of a 20-frame window: the last frame
  // lies outside the band around the mean of the last 8, so no steady state.
  const CheckResult r = judge_blend_lag(p, {10}, {{"output_luminance", step_curve(30, 10, 100.0, 0.0, 0.9)}});
  EXPECT_EQ(r.verdict, Verdict::fail);
  EXPECT_NE(r.message.find("not settled within 20 frames"), std::string::npos) << r.message;
}

// A run too short for the check (a --frames below the events and lag_limit)
// judges nothing: inconclusive, not a pass.
TEST(BlendLagJudge, NothingJudgedIsInconclusive) {
  BlendLagParams p;
  p.lag_limit = 90;
  const CheckResult r = judge_blend_lag(p, {60}, {{"output_luminance", std::vector<double>(40, 1.0)}});
  EXPECT_EQ(r.verdict, Verdict::inconclusive) << r.message;
  EXPECT_NE(r.message.find("judged nothing"), std::string::npos) << r.message;
}

TEST(BlendLagJudge, NoisyStaticWindowFails) {
  BlendLagParams p;
  std::vector<double> v(60, 100.0);
  for (std::size_t t = 0; t < v.size(); ++t) v[t] += (t % 2 ? 1.5 : -1.5);  // 3 % jumps
  const CheckResult r = judge_blend_lag(p, {}, {{"output_luminance", v}});
  EXPECT_EQ(r.verdict, Verdict::fail);
  EXPECT_NEAR(r.figures["max_static_variation"].get<double>(), 0.03, 1e-3);
  p.delta = 0.05;
  EXPECT_EQ(judge_blend_lag(p, {}, {{"output_luminance", v}}).verdict, Verdict::pass);
}

// The response: frames from the event to the first frame outside the old
// level's band. A step on the event's frame responds at 0; the same step a
// frame later at 1, which response_limit 0 fails and the lag alone cannot
// tell apart.
TEST(BlendLagJudge, AOneFrameLateResponseFailsAResponseLimitOfZero) {
  BlendLagParams p;
  p.steady_frames = 3;
  const std::vector<double> on_time = step_curve(40, 4, 1.0, 10.0, 0.5);
  std::vector<double> late = on_time;
  late.insert(late.begin() + 4, 1.0);  // everything from the event one frame later
  late.pop_back();
  const CheckResult unjudged = judge_blend_lag(p, {4}, {{"output_luminance", late}});
  EXPECT_EQ(unjudged.verdict, Verdict::pass) << unjudged.message;
  EXPECT_EQ(unjudged.figures["max_response_frames"], 1);
  p.response_limit = 0;
  const CheckResult good = judge_blend_lag(p, {4}, {{"output_luminance", on_time}});
  EXPECT_EQ(good.verdict, Verdict::pass) << good.message;
  EXPECT_EQ(good.figures["max_response_frames"], 0);
  const CheckResult bad = judge_blend_lag(p, {4}, {{"output_luminance", late}});
  EXPECT_EQ(bad.verdict, Verdict::fail);
  EXPECT_NE(bad.message.find("first moved 1 frame(s) after the event at frame 4 > 0"), std::string::npos)
      << bad.message;
  EXPECT_EQ(bad.first_failing_frame, 4u);
}

gpu::WorldCacheFrameStats stats(std::uint32_t active, std::uint32_t over_age, std::uint32_t oldest) {
  gpu::WorldCacheFrameStats s;
  s.active_cells = s.live_cells = active;
  s.over_age_cells = over_age;
  s.oldest_age = oldest;
  return s;
}

TEST(CacheLifetimeJudge, CellsPastLifetimeFailWithCountAndOldestAge) {
  CacheLifetimeParams p;
  p.lifetime = 30;
  CacheLifetimeCheck ok(p), immortal(p);
  for (std::uint32_t f = 0; f < 40; ++f) {
    ok.record_frame(f, stats(100, 0, std::min(f, 31u)));
    immortal.record_frame(f, stats(100, f > 31 ? 7 : 0, f));
  }
  EXPECT_EQ(ok.result().verdict, Verdict::pass) << ok.result().message;
  const CheckResult r = immortal.result();
  EXPECT_EQ(r.verdict, Verdict::fail);
  EXPECT_EQ(r.first_failing_frame, 32u);
  EXPECT_NE(r.message.find("7 cells past lifetime + 1 = 31 frames"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("oldest age 32 frames"), std::string::npos) << r.message;
}

TEST(CacheLifetimeJudge, OccupancyMustReturnToItsLevel) {
  CacheLifetimeParams p;
  p.occupancy_frames = std::array<std::uint32_t, 2>{5, 50};
  CacheLifetimeCheck back(p), grown(p);
  for (std::uint32_t f = 0; f < 60; ++f) {
    back.record_frame(f, stats(f < 10 || f > 40 ? 1000 : 3000, 0, 1));
    grown.record_frame(f, stats(f < 10 ? 1000 : 3000, 0, 1));
  }
  EXPECT_EQ(back.result().verdict, Verdict::pass) << back.result().message;
  EXPECT_EQ(grown.result().verdict, Verdict::fail);
  EXPECT_EQ(grown.result().figures["occupancy_ratio"], 3.0);
}

// The scenarios, run in-process with a 2^16-cell table (--set) so that each
// takes seconds on lavapipe; everything else is the scenario's own profile.
RunResult run(const std::string& scenario, const std::vector<std::string>& sets, const std::string& tag) {
  static test::TempDir dir("cache_checks");
  RunOptions o;
  o.quiet = true;
  o.out_dir = dir.path() / tag;
  o.sets = sets;
  o.sets.push_back("world_cache.cells=65536");
  return run_scenario(load_scenario(test::source_dir() / "scenarios" / scenario), o);
}

const CheckResult& check(const RunResult& r, const std::string& name) {
  for (const CheckResult& c : r.checks)
    if (c.name == name) return c;
  throw std::runtime_error("no check " + name);
}

// blend_lag's lag per lighting event (frames until cache_mean_radiance stays
// within ε of its new level), in event order.
std::vector<int> event_lags(const CheckResult& lag) {
  std::vector<int> lags;
  for (const nlohmann::json& e : lag.figures["events"]) lags.push_back(e["lag_frames"].get<int>());
  return lags;
}

// The two light-toggle scenarios under 0.18 and under 0.17's fixed blend
// (blend=fixed, max_samples=20). Their lags (cache_mean_radiance, ε 5 %),
// measured with this 2^16-cell table on lavapipe, 2026-12-02, bit-identical
// across runs (the tests print them):
//
//   scenario (lag_limit)  0.18 adaptive, light off / on   fixed blend
//   closed room (90)      62 / 78                         104 / 104
//   sunlit yard (35)      22 / 27                         46 / 46
//
// The bounds:
// - 0.18 passes: the check's own verdict against the scenario's lag_limit,
//   which the scenario puts between the adaptive and the fixed blend's lags
//   (its description has the 0.17/0.18/0.19 figures).
// - The fixed blend fails for its lag, not for δ: its largest lag is above
//   the same lag_limit, read from the check's limits (by 14 frames in the
//   room, 11 in the yard).
// - At each event the fixed blend lags the adaptive one, which is what the
//   adaptive blend is for (room: by 42 and 26 frames, yard: 24 and 19).
// A lone 1/20 blend leaves 0.95^n of a step: within 5 % of a step to nearly
// zero from n = ln 0.05 / ln 0.95 = 58 frames. The room takes longer (104):
// light cannot leave it and the cache samples itself, so bounced light
// fades with the cells it comes from. The yard is quicker (46): light
// escapes to the sky (a smaller step relative to the level, 88 % instead
// of 97 %), and a cell below the 20-sample cap blends 1/(samples + 1).
void expect_adaptive_passes_and_fixed_lags(const RunResult& adaptive, const RunResult& fixed) {
  EXPECT_EQ(check(adaptive, "cache_lifetime").verdict, Verdict::pass) << check(adaptive, "cache_lifetime").message;
  const CheckResult& good = check(adaptive, "blend_lag");
  EXPECT_EQ(good.verdict, Verdict::pass) << good.message;
  const CheckResult& lag = check(fixed, "blend_lag");
  EXPECT_EQ(lag.verdict, Verdict::fail);
  EXPECT_NE(lag.message.find("frames"), std::string::npos) << lag.message;
  EXPECT_GT(lag.figures["max_lag_frames"].get<int>(), lag.limits["lag_frames"].get<int>()) << lag.message;
  const std::vector<int> a = event_lags(good), f = event_lags(lag);
  ASSERT_EQ(a.size(), 2u) << good.figures.dump();  // light off, light on
  ASSERT_EQ(f.size(), 2u) << lag.figures.dump();
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_GT(f[i], a[i]) << "event " << i;
}

TEST(CacheChecksScenario, ClosedRoom018PassesAndFixedBlendLags) {
  const RunResult good = run("cache_light_toggle_closed_room.json", {}, "room_018");
  const RunResult fixed = run("cache_light_toggle_closed_room.json", {"world_cache.blend=fixed", "world_cache.max_samples=20"},
                              "room_fixed");
  expect_adaptive_passes_and_fixed_lags(good, fixed);
  std::cout << "closed room lag, 0.18: " << check(good, "blend_lag").figures["events"].dump() << "\n"
            << "closed room lag, fixed blend: " << check(fixed, "blend_lag").figures["events"].dump() << "\n";
}

// Bevy #21348: the cache reading last frame's light tiles answers a light
// change a frame late (scenarios/bugs/bevy_21348_cache_reads_last_frames_tiles.json);
// 0.18's order answers on the change's frame (cache_light_response_cornell.json).
TEST(CacheChecksScenario, CacheAnswersALightChangeOnItsFrameUnlessItReadsLastFramesTiles) {
  const RunResult fixed = run("cache_light_response_cornell.json", {}, "response_018");
  const CheckResult& ok = check(fixed, "blend_lag");
  EXPECT_EQ(ok.verdict, Verdict::pass) << ok.message;
  EXPECT_EQ(ok.figures["max_response_frames"], 0);
  const RunResult stale =
      run("cache_light_response_cornell.json", {"world_cache.light_tiles_frame=previous"}, "response_previous");
  const CheckResult& bad = check(stale, "blend_lag");
  EXPECT_EQ(bad.verdict, Verdict::fail);
  EXPECT_EQ(bad.figures["max_response_frames"], 1) << bad.message;
}

TEST(CacheChecksScenario, Sweep018PassesAndFullLifetimeRuleFails) {
  const RunResult good = run("cache_sweep_room_and_yard.json", {}, "sweep_018");
  const CheckResult& ok = check(good, "cache_lifetime");
  EXPECT_EQ(ok.verdict, Verdict::pass) << ok.message;
  const RunResult full = run("cache_sweep_room_and_yard.json", {"world_cache.cache_to_cache_life=full"}, "sweep_full");
  const CheckResult& bad = check(full, "cache_lifetime");
  EXPECT_EQ(bad.verdict, Verdict::fail);
  EXPECT_NE(bad.message.find("cells past lifetime + 1 = 31 frames"), std::string::npos) << bad.message;
  EXPECT_NE(bad.message.find("oldest age"), std::string::npos) << bad.message;
  std::cout << "sweep peak active cells: atomic_max " << ok.figures["peak_active_cells"] << ", full "
            << bad.figures["peak_active_cells"] << "; " << bad.message << "\n";
}

TEST(CacheChecksScenario, Yard018PassesAndFixedBlendLags) {
  const RunResult good = run("cache_light_toggle_yard.json", {}, "yard_018");
  const RunResult fixed = run("cache_light_toggle_yard.json", {"world_cache.blend=fixed", "world_cache.max_samples=20"},
                              "yard_fixed");
  expect_adaptive_passes_and_fixed_lags(good, fixed);
  std::cout << "yard lag, 0.18: " << check(good, "blend_lag").figures["events"].dump() << "\n"
            << "yard lag, fixed blend: " << check(fixed, "blend_lag").figures["events"].dump() << "\n";
}

// The cache view (a cache query at every primary surface, Bevy's debug
// VISUALIZE_WORLD_CACHE) is off unless the scenario asks for it: then GI's
// queries alone feed the cache, as in Bevy. Asked for, its queries keep
// cells alive that no GI ray touches, and the frame record and the timings
// show it.
// In the closed room GI's rays reach every surface the camera sees (the same
// 1434 cells either way); over the open field they do not.
TEST(CacheView, OffUnlessAskedAndItsQueriesAddCells) {
  Scenario scenario = load_scenario(test::source_dir() / "scenarios/cache_open_field.json");
  scenario.checks.erase(std::remove_if(scenario.checks.begin(), scenario.checks.end(),
                                       [](const CheckSpec& c) { return c.name != "finite"; }),
                        scenario.checks.end());
  static test::TempDir dir("cache_view");
  RunOptions o;
  o.quiet = true;
  o.frames = 24;
  o.sets = {"world_cache.cells=65536"};
  o.out_dir = dir.path() / "off";
  const RunResult off = run_scenario(scenario, o);
  scenario.cache_view = true;
  o.out_dir = dir.path() / "on";
  const RunResult on = run_scenario(scenario, o);
  ASSERT_EQ(off.exit_code, 0);
  ASSERT_EQ(on.exit_code, 0);
  const nlohmann::json& last_off = off.summary["frames"].back()["world_cache"];
  const nlohmann::json& last_on = on.summary["frames"].back()["world_cache"];
  EXPECT_FALSE(last_off.contains("view_mean_luminance")) << last_off.dump();
  EXPECT_GT(last_on["view_mean_luminance"].get<double>(), 0.0) << last_on.dump();
  EXPECT_FALSE(off.summary["timings"]["passes"].contains("world_cache_view")) << off.summary["timings"].dump();
  EXPECT_TRUE(on.summary["timings"]["passes"].contains("world_cache_view")) << on.summary["timings"].dump();
  EXPECT_GT(last_off["live_cells"].get<int>(), 0);
  EXPECT_GT(last_on["live_cells"].get<int>(), last_off["live_cells"].get<int>());
  std::cout << "live cells at frame 23: GI's queries " << last_off["live_cells"] << ", with the view "
            << last_on["live_cells"] << "\n";
}

// The debug signal needs the debug view, and the cache checks need GI (or
// the view) to fill the cache: clear errors naming the JSON path.
TEST(CacheView, SignalsAndChecksThatNeedAFedCacheAreRefused) {
  Scenario scenario = load_scenario(test::source_dir() / "scenarios/cache_light_toggle_closed_room.json");
  for (CheckSpec& c : scenario.checks)
    if (c.name == "blend_lag") c.params["signals"] = {"cache_view_luminance"};
  try {
    blend_lag_params(*scenario.find_check("blend_lag"), scenario);
    FAIL() << "cache_view_luminance without the view was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"cache_view\": true"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/signals/0"), std::string::npos) << e.what();
  }
  scenario.cache_view = true;
  EXPECT_NO_THROW(blend_lag_params(*scenario.find_check("blend_lag"), scenario));

  Scenario dark = load_scenario(test::source_dir() / "scenarios/cache_light_toggle_closed_room.json");
  dark.gi = false;
  for (CheckSpec& c : dark.checks)
    if (c.name == "blend_lag") c.params.erase("signals");
  static test::TempDir dir("cache_view_refused");
  RunOptions o;
  o.quiet = true;
  o.out_dir = dir.path();
  try {
    run_scenario(dark, o);
    FAIL() << "cache_lifetime without GI was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("only GI's queries fill"), std::string::npos) << e.what();
  }
}

// The expected failure scenarios/expected_failures/cache_light_toggle_cornell_0_18_noise.json
// (a finding about 0.18's adaptive blend with few cells), run as the nightly
// would, with its own 2^20-cell table (about 40 s on lavapipe): what its
// description documents must still hold. Measured on lavapipe, 2026-12-02,
// seed 12: 75 live cells at most (the closed room keeps 1446); cache_mean_radiance
// settles 59 frames after light-off (within the limit of 80) but 107 after
// light-on, and jumps 5.62 % in one frame at frame 317 (δ 4 %). The bounds are
// the check's own (lag_limit and δ, read from its limits), applied to the
// event each failure is documented for; the cell bound is twice the measured
// count, an order of magnitude below the room's.
TEST(CacheChecksScenario, OpenCornellBoxExpectedFailureFailsBlendLag) {
  static test::TempDir dir("cache_cornell_noise");
  RunOptions o;
  o.quiet = true;
  o.out_dir = dir.path();
  const RunResult r = run_scenario(
      load_scenario(test::source_dir() / "scenarios/expected_failures/cache_light_toggle_cornell_0_18_noise.json"), o);
  EXPECT_EQ(r.exit_code, 1);
  const CheckResult& life = check(r, "cache_lifetime");
  EXPECT_EQ(life.verdict, Verdict::pass) << life.message;
  EXPECT_LT(life.figures["peak_active_cells"].get<int>(), 150) << "no longer a scene of few cells";
  const CheckResult& lag = check(r, "blend_lag");
  EXPECT_EQ(lag.verdict, Verdict::fail);
  const int limit = lag.limits["lag_frames"].get<int>();
  const std::vector<int> lags = event_lags(lag);
  ASSERT_EQ(lags.size(), 2u) << lag.figures.dump();
  EXPECT_LE(lags[0], limit) << "light off (frame 60) settles";
  EXPECT_GT(lags[1], limit) << "light on (frame 210) does not settle within the limit";
  EXPECT_GT(lag.figures["max_static_variation"].get<double>(), lag.limits["delta"].get<double>())
      << "the mean jumps by more than δ once settled";
  std::cout << "open Cornell box, 0.18: " << life.figures["peak_active_cells"] << " cells; " << lag.message << "; "
            << lag.figures["events"].dump() << "\n";
}

TEST(CacheChecksScenario, OpenField018Passes) {
  const RunResult r = run("cache_open_field.json", {}, "field_018");
  EXPECT_EQ(check(r, "cache_lifetime").verdict, Verdict::pass) << check(r, "cache_lifetime").message;
}

}  // namespace
}  // namespace gi
