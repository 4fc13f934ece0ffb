// The check registry (checks/check_registry.h): every check the parser
// accepts is made through it, declares what it reads, and a FrameView holds
// it to that declaration.
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "core/check_catalog.h"
#include "core/errors.h"
#include "core/profile.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "checks/check_registry.h"
#include "replay/run_scenario.h"
#include "tests/test_support.h"

namespace gi {
namespace {

Scenario realtime_gi_scenario(const nlohmann::json& checks) {
  const nlohmann::json doc = {{"name", "registry"},
                              {"scene", {{"generator", "cornell_box"}}},
                              {"resolution", {16, 16}},
                              {"frames", 8},
                              {"mode", "realtime"},
                              {"gi", true},
                              {"checks", checks}};
  return parse_scenario(doc, "registry.json");
}

// Every check file (checks/<name>_check.cpp; realtime_reference is the
// reference check's realtime half) registers its check: a registration the
// linker dropped, or a file that forgot one, fails here.
std::set<std::string> check_files() {
  std::set<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(test::source_dir() / "checks")) {
    const std::string f = e.path().filename().string();
    const std::string suffix = "_check.cpp";
    if (f.size() > suffix.size() && f.compare(f.size() - suffix.size(), suffix.size(), suffix) == 0 &&
        f != "realtime_reference_check.cpp")
      names.insert(f.substr(0, f.size() - suffix.size()));
  }
  return names;
}

TEST(CheckRegistry, EveryDeclaredCheckIsMadeThroughTheRegistry) {
  std::set<std::string> names;
  for (const CheckDeclaration& d : declared_checks()) names.insert(d.name);
  EXPECT_EQ(names, check_files());
  EXPECT_GE(names.size(), 7u);
  nlohmann::json checks = nlohmann::json::array();
  // ray_budget and highlight_noise have no default limit (the scenario's to
  // set); shadow_lag needs the frame of a move (this scenario has none).
  const std::map<std::string, nlohmann::json> required = {
      {"ray_budget", {{"max_rays_per_path", 2.0}}},
      {"highlight_noise", {{"max_relmse", 1.0}}},
      {"shadow_lag", {{"event_frame", 4}, {"settle_frames", 3}}},
      {"motion", {{"frames", {4}}}}};
  // The radiance-cascades checks (rc_*) judge canvas scenarios only.
  nlohmann::json rc_checks = nlohmann::json::array();
  for (const std::string& n : names) {
    nlohmann::json spec = {{"name", n}};
    if (required.count(n)) spec.update(required.at(n));
    if (n.rfind("rc_", 0) == 0) {
      if (n == "rc_light_leak" || n == "rc_penumbra") spec["region"] = {0, 0, 8, 8};
      rc_checks.push_back(spec);
    } else {
      checks.push_back(spec);
    }
  }
  EXPECT_EQ(rc_checks.size(), 5u);
  const Scenario rc = parse_scenario(
      {{"name", "registry_rc"}, {"pipeline", "radiance_cascades"}, {"resolution", {16, 16}}, {"frames", 2},
       {"scene", {{"shapes", {{{"name", "lamp"}, {"type", "ellipse"}, {"center", {8, 8}}, {"radii", {2, 2}}, {"emission", {1, 1, 1}}}}}}},
       {"checks", rc_checks}},
      "registry_rc.json");
  const Profile rc_profile = resolve_profile(rc);
  const Scene no_scene;
  const RunOptions options;
  for (const CheckSpec& spec : rc.checks) {
    const CheckContext c{rc, spec, rc_profile, options, no_scene, rc.frames, rc.seed};
    const std::unique_ptr<Check> check = make_check(c);
    ASSERT_TRUE(check) << spec.name;
    EXPECT_TRUE(check->needs().reads.count(FrameInput::rc_reference)) << spec.name;
  }
  const Scenario s = realtime_gi_scenario(checks);
  const Profile profile = resolve_profile(s);
  const Scene initial = build_scene(s);
  for (const CheckSpec& spec : s.checks) {
    const CheckContext c{s, spec, profile, options, initial, s.frames, s.seed, true, true, true};
    const std::unique_ptr<Check> check = make_check(c);
    ASSERT_TRUE(check) << spec.name;
    // determinism judges no frame of the main run and furnace judges the
    // profile's material model; every other check reads something.
    if (spec.name != "determinism" && spec.name != "furnace") {
      EXPECT_FALSE(check->needs().reads.empty()) << spec.name;
    }
  }
}

TEST(CheckRegistry, TheParserTakesNamesAndKeysFromTheRegistry) {
  EXPECT_THROW(realtime_gi_scenario({{{"name", "no_such_check"}}}), InputError);
  EXPECT_THROW(realtime_gi_scenario({{{"name", "finite"}, {"epsilon", 1}}}), InputError);
  // Parse-time validation declared by the check (reference: spp >= 2).
  try {
    realtime_gi_scenario({{{"name", "reference"}, {"spp", 1}}});
    FAIL() << "spp 1 accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.json_path(), "/checks/0/spp");
  }
}

TEST(CheckRegistry, AFrameViewRefusesWhatTheCheckDidNotDeclare) {
  FrameData data;
  data.frame = 3;
  const Image output(2, 2);
  data.output = &output;
  const std::set<FrameInput> only_output = {FrameInput::output_image};
  const FrameView view(data, only_output);
  EXPECT_NO_THROW(view.output());
  // The output's reduced measures do not open the image (a full readback).
  const std::set<FrameInput> measures = {FrameInput::output};
  const FrameView measured(data, measures);
  EXPECT_NO_THROW(measured.output_luminance());
  EXPECT_THROW(measured.output(), std::logic_error);
  EXPECT_THROW(view.gi_stats(), std::logic_error);
  EXPECT_THROW(view.cache_stats(), std::logic_error);
  EXPECT_THROW(view.chain_frame(0), std::logic_error);
}

TEST(CheckRegistry, AChecksRequestTheRunCannotServeIsBadInputAtItsPath) {
  const Scenario s = realtime_gi_scenario({{{"name", "jacobian"}}, {{"name", "cache_lifetime"}}});
  const Profile profile = resolve_profile(s);
  const Scene initial = build_scene(s);
  const RunOptions options;
  for (const CheckSpec& spec : s.checks) {
    // As if "gi" were off: neither GI statistics nor a fed world cache.
    const CheckContext c{s, spec, profile, options, initial, s.frames, s.seed, true, false, false};
    try {
      make_check(c);
      FAIL() << spec.name << " made without what it reads";
    } catch (const InputError& e) {
      EXPECT_EQ(e.json_path(), spec.json_path + "/name") << e.what();
    }
  }
}

}  // namespace
}  // namespace gi
