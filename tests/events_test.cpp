// Scenario events applied to the scene: interpolation, toggles, spawn and
// despawn, and the rule that the state at frame f is a pure function of
// (initial scene, scenario, f).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/errors.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "core/scenes/cornell_box.h"
#include "core/scene_events.h"

using nlohmann::json;

namespace {

gi::Scenario scenario_with(json events) {
  json doc = {{"name", "events"}, {"scene", {{"generator", "cornell_box"}}}, {"resolution", {16, 9}},
              {"frames", 100}, {"events", std::move(events)}};
  return gi::parse_scenario(doc, "inline_events.json");
}

// The Cornell box plus a directional light "sun".
gi::Scene initial_scene(const gi::Scenario& s) {
  gi::Scene scene = gi::build_scene(gi::parse_scenario(
      json{{"name", "x"}, {"scene", {{"generator", "cornell_box"}}}, {"resolution", {16, 9}}, {"frames", 1}},
      "inline_events.json"));
  gi::DirectionalLight sun;
  sun.name = "sun";
  sun.illuminance = 4.0f;
  sun.color = glm::vec3(1.0f, 0.9f, 0.8f);
  scene.directional_lights.push_back(sun);
  gi::validate_events(s, scene);
  return scene;
}

void expect_same(const gi::Scene& a, const gi::Scene& b) {
  ASSERT_EQ(a.instances.size(), b.instances.size());
  for (std::size_t i = 0; i < a.instances.size(); ++i) {
    EXPECT_EQ(a.instances[i].name, b.instances[i].name);
    EXPECT_EQ(a.instances[i].mesh, b.instances[i].mesh);
    EXPECT_EQ(a.instances[i].material, b.instances[i].material);
    EXPECT_EQ(a.instances[i].transform, b.instances[i].transform) << a.instances[i].name;  // bit for bit
    EXPECT_EQ(a.instances[i].previous_transform, b.instances[i].previous_transform) << a.instances[i].name;
    EXPECT_EQ(a.instances[i].emissive_scale, b.instances[i].emissive_scale);
    EXPECT_EQ(a.instances[i].visible, b.instances[i].visible);
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (std::size_t i = 0; i < a.materials.size(); ++i) {
    EXPECT_EQ(a.materials[i].base_color, b.materials[i].base_color);
    EXPECT_EQ(a.materials[i].emissive, b.materials[i].emissive);
    EXPECT_EQ(a.materials[i].perceptual_roughness, b.materials[i].perceptual_roughness);
  }
  ASSERT_EQ(a.directional_lights.size(), b.directional_lights.size());
  for (std::size_t i = 0; i < a.directional_lights.size(); ++i) {
    EXPECT_EQ(a.directional_lights[i].enabled, b.directional_lights[i].enabled);
    EXPECT_EQ(a.directional_lights[i].illuminance, b.directional_lights[i].illuminance);
    EXPECT_EQ(a.directional_lights[i].color, b.directional_lights[i].color);
  }
  EXPECT_EQ(a.camera.position, b.camera.position);
  EXPECT_EQ(a.camera.target, b.camera.target);
  EXPECT_EQ(a.camera.vertical_fov_degrees, b.camera.vertical_fov_degrees);
  EXPECT_EQ(a.meshes.size(), b.meshes.size());
}

}  // namespace

TEST(Events, CameraKeyframesInterpolateAndHold) {
  gi::Scenario s = scenario_with(json::array({json{{"type", "camera_keyframes"}, {"keys", json::array({
      json{{"frame", 10}, {"position", {0, 0, -2}}, {"target", {0, 0, 0}}, {"fov_y_degrees", 40}},
      json{{"frame", 20}, {"position", {2, 4, -6}}, {"target", {2, 2, 2}}, {"fov_y_degrees", 60}},
      json{{"frame", 24}, {"position", {4, 4, -6}}, {"target", {2, 2, 2}}}})}}}));
  const gi::Scene initial = initial_scene(s);
  gi::Scene scene = initial;
  gi::ChangeSet c = gi::apply_events(scene, initial, s, 0);
  EXPECT_TRUE(c.camera);
  EXPECT_EQ(scene.camera.position, glm::vec3(0, 0, -2));  // held before the first key
  EXPECT_EQ(scene.camera.vertical_fov_degrees, 40.0f);
  c = gi::apply_events(scene, initial, s, 5);
  EXPECT_FALSE(c.any());
  gi::apply_events(scene, initial, s, 15);
  EXPECT_EQ(scene.camera.position, glm::vec3(1, 2, -4));  // exact midpoint
  EXPECT_EQ(scene.camera.target, glm::vec3(1, 1, 1));
  EXPECT_EQ(scene.camera.vertical_fov_degrees, 50.0f);
  EXPECT_EQ(scene.camera.up, initial.camera.up);
  gi::apply_events(scene, initial, s, 22);
  EXPECT_EQ(scene.camera.position, glm::vec3(3, 4, -6));
  EXPECT_EQ(scene.camera.vertical_fov_degrees, 60.0f);  // a key without fov keeps the current one
  c = gi::apply_events(scene, initial, s, 99);
  EXPECT_EQ(scene.camera.position, glm::vec3(4, 4, -6));  // held after the last key
  EXPECT_TRUE(c.camera);
  EXPECT_FALSE(c.lights || c.transforms || c.geometry || c.materials || c.visibility);
}

TEST(Events, CameraSweepLinearAndSmooth) {
  for (const char* ease : {"linear", "smooth"}) {
    gi::Scenario s = scenario_with(json::array({json{{"type", "camera_sweep"}, {"frames", {10, 30}}, {"ease", ease},
        {"from", {{"position", {0, 0, -2}}, {"target", {0, 0, 0}}}},
        {"to", {{"position", {4, 0, -2}}, {"target", {4, 0, 0}}, {"fov_y_degrees", 60}}}}}));
    const gi::Scene initial = initial_scene(s);
    EXPECT_EQ(gi::scene_at_frame(initial, s, 5).camera.position, initial.camera.position);
    EXPECT_EQ(gi::scene_at_frame(initial, s, 10).camera.position, glm::vec3(0, 0, -2));
    EXPECT_EQ(gi::scene_at_frame(initial, s, 20).camera.position, glm::vec3(2, 0, -2));  // smoothstep(0.5) = 0.5
    const float quarter = gi::scene_at_frame(initial, s, 15).camera.position.x;
    EXPECT_FLOAT_EQ(quarter, std::string(ease) == "linear" ? 1.0f : 4.0f * 0.15625f);
    EXPECT_EQ(gi::scene_at_frame(initial, s, 40).camera.position, glm::vec3(4, 0, -2));
    EXPECT_EQ(gi::scene_at_frame(initial, s, 40).camera.vertical_fov_degrees, 60.0f);
  }
}

TEST(Events, LightOffOnToggleEmissiveScaleAndDirectional) {
  gi::Scenario s = scenario_with(json::array({
      json{{"type", "light_off"}, {"frame", 3}, {"light", "light"}},
      json{{"type", "light_off"}, {"frame", 3}, {"light", "sun"}},
      json{{"type", "light_on"}, {"frame", 6}, {"light", "light"}},
      json{{"type", "light_on"}, {"frame", 8}, {"light", "sun"}}}));
  const gi::Scene initial = initial_scene(s);
  const std::uint32_t light = *initial.find_instance("light");
  gi::Scene scene = initial;
  std::vector<gi::ChangeSet> changes;
  for (std::uint32_t f = 0; f < 10; ++f) changes.push_back(gi::apply_events(scene, initial, s, f));
  EXPECT_FALSE(changes[0].any());
  EXPECT_TRUE(changes[3].lights);
  EXPECT_FALSE(changes[4].any());
  EXPECT_TRUE(changes[6].lights);
  EXPECT_TRUE(changes[8].lights);
  EXPECT_FALSE(changes[3].camera || changes[3].transforms || changes[3].geometry);
  gi::Scene at4 = gi::scene_at_frame(initial, s, 4);
  EXPECT_EQ(at4.instances[light].emissive_scale, glm::vec3(0.0f));
  EXPECT_FALSE(at4.directional_lights[0].enabled);
  gi::Scene at7 = gi::scene_at_frame(initial, s, 7);
  EXPECT_EQ(at7.instances[light].emissive_scale, initial.instances[light].emissive_scale);
  EXPECT_FALSE(at7.directional_lights[0].enabled);
  gi::Scene at9 = gi::scene_at_frame(initial, s, 9);
  EXPECT_TRUE(at9.directional_lights[0].enabled);
  EXPECT_EQ(at9.directional_lights[0].illuminance, 4.0f);
  // Every light off and back on: the scene is the initial one again, bit for
  // bit (not compared with itself: `scene` and `at9` are both frame 9).
  expect_same(at9, initial);
  ASSERT_EQ(at9.directional_lights.size(), initial.directional_lights.size());
  for (std::size_t i = 0; i < at9.directional_lights.size(); ++i) {
    EXPECT_EQ(at9.directional_lights[i].enabled, initial.directional_lights[i].enabled);
    EXPECT_EQ(at9.directional_lights[i].illuminance, initial.directional_lights[i].illuminance);
    EXPECT_EQ(at9.directional_lights[i].color, initial.directional_lights[i].color);
  }
}

TEST(Events, LightIntensityAndColor) {
  gi::Scenario s = scenario_with(json::array({
      json{{"type", "light_intensity"}, {"frame", 2}, {"light", "light"}, {"scale", 2.0}},
      json{{"type", "light_intensity"}, {"frames", {10, 20}}, {"light", "light"}, {"scale", 4.0}},
      json{{"type", "light_intensity"}, {"frames", {10, 20}}, {"light", "sun"}, {"scale", 0.5}},
      json{{"type", "light_color"}, {"frame", 30}, {"light", "sun"}, {"color", {0.5, 0.5, 1.0}}},
      json{{"type", "light_off"}, {"frame", 40}, {"light", "light"}},
      json{{"type", "light_intensity"}, {"frame", 41}, {"light", "light"}, {"scale", 1.0}},
      json{{"type", "light_on"}, {"frame", 42}, {"light", "light"}}}));
  const gi::Scene initial = initial_scene(s);
  const std::uint32_t light = *initial.find_instance("light");
  const glm::vec3 e0 = initial.instances[light].emissive_scale;
  EXPECT_EQ(gi::scene_at_frame(initial, s, 5).instances[light].emissive_scale, e0 * 2.0f);
  EXPECT_EQ(gi::scene_at_frame(initial, s, 10).instances[light].emissive_scale, e0 * 2.0f);  // from the current value
  EXPECT_EQ(gi::scene_at_frame(initial, s, 15).instances[light].emissive_scale, e0 * 3.0f);
  EXPECT_EQ(gi::scene_at_frame(initial, s, 25).instances[light].emissive_scale, e0 * 4.0f);
  EXPECT_EQ(gi::scene_at_frame(initial, s, 15).directional_lights[0].illuminance, 4.0f * 0.75f);
  EXPECT_EQ(gi::scene_at_frame(initial, s, 35).directional_lights[0].color, glm::vec3(0.5, 0.5, 1.0));
  EXPECT_EQ(gi::scene_at_frame(initial, s, 41).instances[light].emissive_scale, glm::vec3(0.0f));  // still off
  EXPECT_EQ(gi::scene_at_frame(initial, s, 42).instances[light].emissive_scale, e0);
}

TEST(Events, RangedTransformIsAPureFunctionOfTheFrame) {
  gi::Scenario s = scenario_with(json::array({
      json{{"type", "transform"}, {"frames", {3, 17}}, {"instance", "tall_block"},
           {"translation", {0.1, 0.2, -0.3}}, {"rotation_degrees", {10, 45, 5}}, {"scale", 0.75}},
      json{{"type", "transform"}, {"frames", {10, 40}}, {"instance", "tall_block"}, {"translation", {0, 1, 0}}},
      json{{"type", "material"}, {"frames", {0, 30}}, {"material", "red"}, {"base_color", {0, 0, 1}}},
      json{{"type", "spawn"}, {"frame", 12}, {"instance", "copy"}, {"of", "short_block"}, {"translation", {0, 0.2, 0}}},
      json{{"type", "light_intensity"}, {"frames", {5, 25}}, {"light", "light"}, {"scale", 0.1}}}));
  const gi::Scene initial = initial_scene(s);
  for (std::uint32_t k : {0u, 3u, 4u, 11u, 12u, 17u, 29u, 45u}) {
    SCOPED_TRACE(k);
    gi::Scene stepped = initial;
    for (std::uint32_t f = 0; f <= k; ++f) gi::apply_events(stepped, initial, s, f);
    gi::Scene jumped = initial;
    gi::apply_events(jumped, initial, s, k);
    expect_same(stepped, jumped);
    // From a "snapshot" at a later frame back to k (replay).
    gi::Scene from_later = gi::scene_at_frame(initial, s, 60);
    gi::apply_events(from_later, initial, s, k);
    expect_same(from_later, jumped);
  }
  // Identity at the first frame, full delta at the last.
  const std::uint32_t tall = *initial.find_instance("tall_block");
  EXPECT_EQ(gi::scene_at_frame(initial, s, 3).instances[tall].transform, initial.instances[tall].transform);
  glm::mat4 d = glm::translate(glm::mat4(1.0f), glm::vec3(0.1f, 0.2f, -0.3f));
  d = glm::rotate(d, glm::radians(5.0f), glm::vec3(0, 0, 1));
  d = glm::rotate(d, glm::radians(45.0f), glm::vec3(0, 1, 0));
  d = glm::rotate(d, glm::radians(10.0f), glm::vec3(1, 0, 0));
  d = glm::scale(d, glm::vec3(0.75f));
  EXPECT_EQ(gi::scene_at_frame(initial, s, 9).instances[tall].transform, gi::scene_at_frame(initial, s, 9).instances[tall].transform);
  const glm::mat4 at_end = gi::scene_at_frame(initial, s, 50).instances[tall].transform;
  const glm::mat4 expected = glm::translate(glm::mat4(1.0f), glm::vec3(0, 1, 0)) * d * initial.instances[tall].transform;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_NEAR(at_end[c][r], expected[c][r], 1e-6f);
  // The material halfway.
  const gi::Scene mid = gi::scene_at_frame(initial, s, 15);
  for (const gi::Material& m : mid.materials) {
    if (m.name != "red") continue;
    EXPECT_EQ(m.base_color, glm::vec3(0.63f, 0.065f, 0.05f) * 0.5f + glm::vec3(0, 0, 0.5f));
  }
}

// Each instance's previous transform is its transform one frame earlier,
// only where it moved since (Bevy's PreviousGlobalTransform: last frame's
// GlobalTransform, a new mesh its own); the frame after a move changes the
// motion vectors alone, so it starts no new accumulation window.
TEST(Events, PreviousTransformIsLastFramesWhereTheInstanceMoved) {
  gi::Scenario s = scenario_with(json::array({
      json{{"type", "transform"}, {"frames", {3, 6}}, {"instance", "short_block"}, {"translation", {0.3, 0, 0}}},
      json{{"type", "transform"}, {"frame", 8}, {"instance", "tall_block"}, {"translation", {0, 0.5, 0}}},
      json{{"type", "spawn"}, {"frame", 5}, {"instance", "copy"}, {"of", "tall_block"}, {"translation", {0, 1, 0}}}}));
  const gi::Scene initial = initial_scene(s);
  const std::uint32_t tall = *initial.find_instance("tall_block");
  const std::uint32_t shorter = *initial.find_instance("short_block");
  gi::Scene scene = initial;
  std::vector<gi::ChangeSet> c;
  std::vector<gi::Scene> at;
  for (std::uint32_t f = 0; f < 11; ++f) {
    c.push_back(gi::apply_events(scene, initial, s, f));
    at.push_back(scene);
  }
  for (std::uint32_t f : {0u, 1u, 2u, 3u, 7u, 10u})
    for (const gi::Instance& i : at[f].instances) EXPECT_FALSE(i.previous_transform) << i.name << " at " << f;
  for (std::uint32_t f : {4u, 5u, 6u}) {  // t = 0 at frame 3: the block moves from frame 4 to 6
    SCOPED_TRACE(f);
    ASSERT_TRUE(at[f].instances[shorter].previous_transform);
    EXPECT_EQ(*at[f].instances[shorter].previous_transform, at[f - 1].instances[shorter].transform);
    EXPECT_NE(at[f].instances[shorter].transform, at[f - 1].instances[shorter].transform);
    EXPECT_FALSE(at[f].instances[tall].previous_transform);
  }
  ASSERT_EQ(at[5].instances.size(), initial.instances.size() + 1);
  EXPECT_FALSE(at[5].instances.back().previous_transform) << "a spawn's first frame has no motion";
  ASSERT_TRUE(at[8].instances[tall].previous_transform);
  EXPECT_EQ(*at[8].instances[tall].previous_transform, initial.instances[tall].transform);
  EXPECT_FALSE(at[9].instances[tall].previous_transform);
  // The frame after each move: motion only.
  for (std::uint32_t f : {7u, 9u}) {
    EXPECT_TRUE(c[f].motion) << f;
    EXPECT_FALSE(c[f].any()) << f;
  }
  EXPECT_TRUE(c[8].transforms && c[8].motion);
  EXPECT_FALSE(c[10].motion || c[10].any());
  // A replay from a capture at frame 8 resumes with frame 8's previous transforms.
  expect_same(gi::scene_at_frame(initial, s, 8), at[8]);
}

TEST(Events, SpawnAndDespawn) {
  gi::Scenario s = scenario_with(json::array({
      json{{"type", "spawn"}, {"frame", 4}, {"instance", "light2"}, {"of", "light"}, {"translation", {0, -0.1, 0}}},
      json{{"type", "spawn"}, {"frame", 6}, {"instance", "light3"}, {"of", "light2"}, {"scale", 2}},
      json{{"type", "light_off"}, {"frame", 7}, {"light", "light2"}},
      json{{"type", "despawn"}, {"frame", 8}, {"instance", "light2"}},
      json{{"type", "despawn"}, {"frame", 8}, {"instance", "tall_block"}}}));
  const gi::Scene initial = initial_scene(s);
  const std::size_t n = initial.instances.size();
  const std::uint32_t light = *initial.find_instance("light");
  gi::Scene scene = initial;
  std::vector<gi::ChangeSet> c;
  for (std::uint32_t f = 0; f < 10; ++f) c.push_back(gi::apply_events(scene, initial, s, f));
  EXPECT_TRUE(c[4].geometry);
  EXPECT_TRUE(c[6].geometry);
  EXPECT_FALSE(c[5].any());
  EXPECT_TRUE(c[7].lights);
  EXPECT_FALSE(c[7].geometry);
  EXPECT_TRUE(c[8].visibility);
  EXPECT_FALSE(c[8].geometry);
  ASSERT_EQ(scene.instances.size(), n + 2);
  const gi::Instance& l2 = scene.instances[n];
  EXPECT_EQ(l2.name, "light2");
  EXPECT_EQ(l2.mesh, initial.instances[light].mesh);
  EXPECT_EQ(l2.material, initial.instances[light].material);
  EXPECT_FALSE(l2.visible);
  EXPECT_EQ(l2.emissive_scale, glm::vec3(0.0f));
  EXPECT_EQ(l2.transform, glm::translate(glm::mat4(1.0f), glm::vec3(0, -0.1f, 0)) * initial.instances[light].transform);
  const gi::Instance& l3 = scene.instances[n + 1];
  EXPECT_TRUE(l3.visible);
  EXPECT_EQ(l3.transform, glm::scale(glm::mat4(1.0f), glm::vec3(2.0f)) * l2.transform);
  EXPECT_EQ(l3.emissive_scale, initial.instances[light].emissive_scale);
  EXPECT_FALSE(scene.instances[*initial.find_instance("tall_block")].visible);
  EXPECT_EQ(scene.find_instance("light3"), n + 1);
  // Back before the spawns (replay from an earlier capture): gone again.
  c[0] = gi::apply_events(scene, initial, s, 2);
  EXPECT_TRUE(c[0].geometry);
  expect_same(scene, initial);
}

// remove_raytracing_mesh hides the instance in the scene every reference sees
// and marks why, so the frame loop can keep it in the renderer where the
// profile re-creates Bevy #24764 (scene.raytracing_mesh_removal "ignored").
TEST(Events, RemoveRaytracingMeshHidesTheInstanceAndSaysWhy) {
  gi::Scenario s = scenario_with(json::array({
      json{{"type", "remove_raytracing_mesh"}, {"frame", 3}, {"instance", "tall_block"}},
      json{{"type", "despawn"}, {"frame", 3}, {"instance", "short_block"}}}));
  const gi::Scene initial = initial_scene(s);
  const std::uint32_t tall = *initial.find_instance("tall_block");
  const std::uint32_t shortb = *initial.find_instance("short_block");
  gi::Scene scene = initial;
  EXPECT_FALSE(gi::apply_events(scene, initial, s, 2).any());
  EXPECT_TRUE(scene.instances[tall].visible);
  const gi::ChangeSet c = gi::apply_events(scene, initial, s, 3);
  EXPECT_TRUE(c.visibility);
  EXPECT_FALSE(c.geometry);
  EXPECT_FALSE(scene.instances[tall].visible);
  EXPECT_TRUE(scene.instances[tall].raytracing_mesh_removed);
  EXPECT_FALSE(scene.instances[shortb].visible);
  EXPECT_FALSE(scene.instances[shortb].raytracing_mesh_removed);
}

TEST(Events, UnknownNamesAreInputErrors) {
  auto error_path = [](json events) -> std::string {
    gi::Scenario s = scenario_with(std::move(events));
    try {
      initial_scene(s);
    } catch (const gi::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("inline_events.json"), std::string::npos);
      return e.json_path();
    }
    return "accepted";
  };
  EXPECT_EQ(error_path(json::array({json{{"type", "despawn"}, {"frame", 1}, {"instance", "nope"}}})),
            "/events/0/instance");
  EXPECT_EQ(error_path(json::array({json{{"type", "remove_raytracing_mesh"}, {"frame", 1}, {"instance", "nope"}}})),
            "/events/0/instance");
  EXPECT_EQ(error_path(json::array({json{{"type", "material"}, {"frame", 1}, {"material", "nope"}, {"metallic", 1}}})),
            "/events/0/material");
  // Spawned later than it is used: the order is (frame, position), not the file's.
  EXPECT_EQ(error_path(json::array({json{{"type", "spawn"}, {"frame", 5}, {"instance", "b"}, {"of", "light"}},
                                    json{{"type", "transform"}, {"frame", 4}, {"instance", "b"}}})),
            "/events/1/instance");
  EXPECT_EQ(error_path(json::array({json{{"type", "transform"}, {"frame", 6}, {"instance", "b"}},
                                    json{{"type", "spawn"}, {"frame", 5}, {"instance", "b"}, {"of", "light"}}})),
            "accepted");
  EXPECT_EQ(error_path(json::array({json{{"type", "spawn"}, {"frame", 5}, {"instance", "red_wall"}, {"of", "light"}}})),
            "/events/0/instance");
}
