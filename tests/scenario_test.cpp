// Scenario parsing: bad files name the file and the JSON path; the schema
// (scenarios/schema.json) and the parser agree on keys, enums and verdicts.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validator.hpp>

#include "core/check_catalog.h"
#include "core/errors.h"
#include "core/scenario.h"
#include "core/scene_builder.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path kSource = GIHARNESS_SOURCE_DIR;
const fs::path kBad = kSource / "tests/data/scenarios/bad";
const fs::path kGood = kSource / "tests/data/scenarios/good";

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

// ---- The schema, read by valijson (libvalijson-dev). Debian bookworm's
// valijson 1.0 reads JSON Schema draft 7; schema.json is 2020-12. The subset
// schema.json uses differs from draft 7 in one place only: a tuple is
// `prefixItems` + `items` (the rest) in 2020-12, `items` (an array) +
// `additionalItems` in draft 7. as_draft7 rewrites that and fails the test on
// any keyword valijson does not implement (it would ignore it silently, and a
// constraint the schema states would go unchecked). `$defs` needs nothing:
// valijson resolves "#/$defs/..." as a JSON Pointer into the document, and
// `$ref`'s siblings in schema.json are only descriptions (draft 7 ignores
// them, 2020-12 applies them; checked below).
const std::set<std::string> kDraft7Keywords = {
    // what valijson 1.0 validates
    "$ref", "type", "enum", "const", "properties", "additionalProperties", "required", "items", "additionalItems",
    "minItems", "maxItems", "uniqueItems", "contains", "minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum",
    "multipleOf", "pattern", "minLength", "maxLength", "minProperties", "maxProperties", "patternProperties",
    "propertyNames", "dependencies", "oneOf", "anyOf", "allOf", "not", "if", "then", "else",
    // annotations, and the container of definitions (never validated)
    "$schema", "$id", "$defs", "$comment", "title", "description", "default", "examples"};
const std::set<std::string> kAnnotations = {"$schema", "$id", "$comment", "title", "description", "default", "examples"};

json as_draft7(json s, const std::string& where = "") {
  if (s.is_boolean()) return s;
  if (!s.is_object()) {
    ADD_FAILURE() << "schema at " << where << " is neither an object nor a boolean";
    return s;
  }
  if (s.contains("prefixItems")) {
    json rest = s.contains("items") ? s["items"] : json(true);
    s["items"] = s["prefixItems"];
    s["additionalItems"] = rest;
    s.erase("prefixItems");
  }
  if (s.contains("$ref"))
    for (auto it = s.begin(); it != s.end(); ++it)
      if (it.key() != "$ref" && !kAnnotations.count(it.key()))
        ADD_FAILURE() << where << ": \"" << it.key() << "\" beside $ref (draft 7 would ignore it)";
  for (auto it = s.begin(); it != s.end(); ++it) {
    const std::string& k = it.key();
    const std::string at = where + "/" + k;
    if (!kDraft7Keywords.count(k))
      ADD_FAILURE() << "valijson (draft 7) does not implement \"" << k << "\" at " << (where.empty() ? "/" : where);
    if (k == "properties" || k == "patternProperties" || k == "$defs" || k == "dependencies") {
      for (auto p = it->begin(); p != it->end(); ++p)
        if (!p->is_array()) *p = as_draft7(*p, at + "/" + p.key());  // dependencies may list names
    } else if (k == "items" || k == "allOf" || k == "anyOf" || k == "oneOf") {
      if (it->is_array()) {
        for (std::size_t i = 0; i < it->size(); ++i) (*it)[i] = as_draft7((*it)[i], at + "/" + std::to_string(i));
      } else {
        *it = as_draft7(*it, at);
      }
    } else if (k == "additionalProperties" || k == "additionalItems" || k == "contains" || k == "propertyNames" ||
               k == "not" || k == "if" || k == "then" || k == "else") {
      *it = as_draft7(*it, at);
    }
  }
  return s;
}

json schema() { return read_json(kSource / "scenarios/schema.json"); }

class SchemaValidator {
 public:
  explicit SchemaValidator(const json& schema_2020_12) : draft7_(as_draft7(schema_2020_12)) {
    valijson::SchemaParser parser(valijson::SchemaParser::kDraft7);
    valijson::adapters::NlohmannJsonAdapter adapter(draft7_);
    parser.populateSchema(adapter, schema_);
  }
  bool valid(const json& doc) const {
    valijson::Validator validator(valijson::Validator::kStrongTypes);
    valijson::adapters::NlohmannJsonAdapter adapter(doc);
    return validator.validate(schema_, adapter, nullptr);
  }

 private:
  json draft7_;
  valijson::Schema schema_;
};

std::vector<std::string> keys_of(const json& properties) {
  std::vector<std::string> k;
  for (auto it = properties.begin(); it != properties.end(); ++it) k.push_back(it.key());
  return k;
}
std::set<std::string> as_set(const std::vector<std::string>& v) { return {v.begin(), v.end()}; }
std::set<std::string> as_set(const json& a) { return {a.begin(), a.end()}; }

// Every scenario file the repository holds (schema and profiles aside).
std::vector<fs::path> scenario_files() {
  std::vector<fs::path> files;
  for (const fs::path& dir : {kSource / "scenarios", kGood, kBad})
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      const fs::path& p = e.path();
      if (p.extension() != ".json" || p.filename() == "schema.json") continue;
      if (p.string().find("/profiles/") != std::string::npos || p.string().find("/assets/") != std::string::npos) continue;
      files.push_back(p);
    }
  std::sort(files.begin(), files.end());
  return files;
}

bool parser_accepts(const json& doc, const fs::path& file) {
  try {
    gi::parse_scenario(doc, file);
    return true;
  } catch (const gi::InputError&) {
    return false;
  }
}

}  // namespace

// ---- Bad files: every one is an InputError naming the file and the path.
struct BadCase {
  const char* file;
  const char* path;   // JSON Pointer of the offending value ("" = the document)
  bool at_build;      // rejected by build_scene (the scene is needed), not by load_scenario
  const char* also;   // a further piece of the message
};

const BadCase kBadCases[] = {
    {"malformed_json.json", "", false, "line 5, column"},
    {"wrong_type.json", "/frames", false, "integer"},
    {"unknown_event_type.json", "/events/3/type", false, "got \"light_of\""},
    {"unknown_key.json", "/events/0/translate", false, "unknown key \"translate\""},
    {"unknown_top_level_key.json", "/frame_count", false, "expected one of: $schema, name"},
    {"out_of_range.json", "/resolution/1", false, "1..8192"},
    {"missing_scene_file.json", "/scene/gltf", false, "does_not_exist.gltf"},
    {"unknown_check.json", "/checks/1/name", false, "got \"energy\""},
    {"frames_on_one_frame_event.json", "/events/0/frames", false, "unknown key"},
    {"unknown_light_name.json", "/events/0/light", true, "\"lamp\""},
    {"unknown_generator.json", "/scene/generator", true, "\"cornel_box\""},
    {"unknown_mesh_generator.json", "/events/0/mesh/generator", true, "unknown mesh generator"},
    // The radiance-cascades pipeline: its own checks, events, shapes and keys.
    {"rc_solari_check.json", "/checks/0/name", false, "expected an rc_* check"},
    {"rc_spawn_event.json", "/events/0/type", false, "for the radiance_cascades pipeline, got \"despawn\""},
    {"rc_light_on_occluder.json", "/events/0/light", false, "an emitting shape, got \"wall\""},
    {"rc_bad_shape.json", "/scene/shapes/1/radii", false, "positive radii"},
    {"rc_solari_key.json", "/gi", false, "belongs to Solari's"},
    // Hostile input, refused by the guarded reader (core/json_input.h) before the parser walks it.
    {"duplicate_key.json", "/frames", false, "\"frames\" is there twice"},
    {"number_overflow.json", "/scene/params/light_scale", false, "a number a double holds"},
    {"deep_nesting.json", "/description/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/…", false, "nested at most 256 deep; deeper at line 3"},
    {"byte_order_mark.json", "", false, "byte-order mark"},
};

TEST(Scenario, EveryBadFileIsAnInputErrorWithFileAndPath) {
  std::set<std::string> covered;
  for (const BadCase& c : kBadCases) {
    SCOPED_TRACE(c.file);
    covered.insert(c.file);
    const fs::path file = kBad / c.file;
    try {
      gi::Scenario s = gi::load_scenario(file);
      ASSERT_TRUE(c.at_build) << "load_scenario accepted it";
      gi::build_scene(s);
      FAIL() << "build_scene accepted it";
    } catch (const gi::InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.json_path(), c.path) << what;
      EXPECT_NE(what.find(c.file), std::string::npos) << what;
      EXPECT_NE(what.find(std::string(": ") + (*c.path ? c.path : "/") + ": "), std::string::npos) << what;
      EXPECT_NE(what.find(c.also), std::string::npos) << what;
    }
  }
  for (const auto& e : fs::directory_iterator(kBad))
    EXPECT_TRUE(covered.count(e.path().filename().string())) << e.path() << " has no case in kBadCases";
}

TEST(Scenario, CornellBoxScenario) {
  gi::Scenario s = gi::load_scenario(kSource / "scenarios/cornell_box.json");
  EXPECT_EQ(s.name, "cornell_box");
  EXPECT_EQ(s.resolution[0], 320u);
  EXPECT_EQ(s.resolution[1], 180u);
  EXPECT_EQ(s.frames, 64u);
  EXPECT_EQ(s.seed, 1u);
  EXPECT_EQ(s.profile, "solari-0.18");
  EXPECT_EQ(s.mode, gi::RenderMode::Reference);
  ASSERT_EQ(s.checks.size(), 2u);
  EXPECT_EQ(s.checks[0].name, "finite");
  EXPECT_EQ(s.checks[1].name, "reference");
  EXPECT_EQ(s.raw["description"], s.description);
  gi::Scene scene = gi::build_scene(s);
  EXPECT_TRUE(scene.find_instance("light"));
}

TEST(Scenario, DefaultsAndRawKept) {
  json doc = {{"name", "x"}, {"scene", {{"generator", "cornell_box"}}}, {"resolution", {8, 4}}, {"frames", 3},
              {"overrides", {{"a.b", 1}}}};
  gi::Scenario s = gi::parse_scenario(doc, "inline.json");
  EXPECT_EQ(s.seed, 1u);
  EXPECT_EQ(s.profile, "solari-0.18");
  EXPECT_EQ(s.mode, gi::RenderMode::Realtime);
  EXPECT_EQ(s.samples_per_frame, 1u);
  EXPECT_EQ(s.overrides["a.b"], 1);
  EXPECT_EQ(s.raw, doc);
}

// "background" (Bevy's ClearColor) reaches the scene; a negative channel is
// an input error at its JSON path.
TEST(Scenario, BackgroundReachesTheSceneAndIsChecked) {
  json doc = {{"name", "x"}, {"scene", {{"generator", "cornell_box"}}}, {"resolution", {8, 4}}, {"frames", 3}};
  EXPECT_EQ(gi::build_scene(gi::parse_scenario(doc, "inline.json")).background, glm::vec3(0.0f));
  doc["background"] = {0.25, 0.5, 1.0};
  EXPECT_EQ(gi::build_scene(gi::parse_scenario(doc, "inline.json")).background, glm::vec3(0.25f, 0.5f, 1.0f));
  doc["background"] = {0.25, -0.5, 1.0};
  try {
    gi::parse_scenario(doc, "inline.json");
    FAIL() << "a negative background was accepted";
  } catch (const gi::InputError& e) {
    EXPECT_EQ(e.json_path(), "/background/1") << e.what();
  }
}

// A repeated spawn is expanded into plain spawns: frames, zero-padded names
// and grid translations as SpawnRepeat says; a name without '#' is refused.
TEST(Scenario, RepeatedSpawnExpandsIntoNumberedSpawnsOnAGrid) {
  json doc = {{"name", "grid"},
              {"scene", {{"generator", "cliff"}, {"params", {{"triangles", 12}}}}},
              {"resolution", {8, 8}},
              {"frames", 20},
              {"events", json::array({json{{"type", "spawn"},
                                           {"frame", 2},
                                           {"instance", "c_###"},
                                           {"of", "cliff"},
                                           {"translation", {1.0, 0.0, 0.0}},
                                           {"repeat",
                                            {{"count", 5},
                                             {"frame_step", 3},
                                             {"first_number", 8},
                                             {"columns", 2},
                                             {"first_cell", 1},
                                             {"step", {10.0, 0.0, 0.0}},
                                             {"row_step", {0.0, 0.0, -5.0}}}}}})},
              {"checks", json::array({json{{"name", "finite"}}})}};
  const gi::Scenario s = gi::parse_scenario(doc, "grid.json");
  ASSERT_EQ(s.events.size(), 5u);
  const std::vector<std::string> names = {"c_008", "c_009", "c_010", "c_011", "c_012"};
  // cells 1..5 in rows of 2: (1,0) (0,1) (1,1) (0,2) (1,2)
  const std::vector<glm::vec3> at = {{11, 0, 0}, {1, 0, -5}, {11, 0, -5}, {1, 0, -10}, {11, 0, -10}};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(s.events[i].type, gi::EventType::Spawn);
    EXPECT_EQ(s.events[i].first, 2u + 3u * i);
    EXPECT_EQ(s.events[i].instance, names[i]);
    EXPECT_EQ(s.events[i].translation, at[i]) << i;
    EXPECT_EQ(s.events[i].of, "cliff");
    EXPECT_FALSE(s.events[i].repeat.has_value());
  }
  doc["events"][0]["instance"] = "c";
  try {
    gi::parse_scenario(doc, "grid.json");
    FAIL() << "a repeated spawn without '#' was accepted";
  } catch (const gi::InputError& e) {
    EXPECT_EQ(e.json_path(), "/events/0/instance");
  }
}

TEST(Scenario, AllEventsScenarioParsesAndBuilds) {
  gi::Scenario s = gi::load_scenario(kGood / "all_events.json");
  ASSERT_EQ(s.events.size(), 13u);  // the last, a repeated spawn, stands for 3
  EXPECT_EQ(s.events[12].instance, "row_03");
  EXPECT_EQ(s.events[0].type, gi::EventType::CameraKeyframes);
  EXPECT_EQ(s.events[4].first, 10u);
  EXPECT_EQ(s.events[4].last, 20u);
  EXPECT_TRUE(s.events[4].ranged);
  EXPECT_EQ(s.events[7].scale3, glm::vec3(1, 2, 1));
  EXPECT_EQ(s.find_check("reference")->params["spp"], 256);
  EXPECT_EQ(s.find_check("blend_lag")->params["epsilon"], 0.05);
  gi::build_scene(s);
  // Applied in (frame, position) order.
  std::vector<std::size_t> order = gi::event_order(s);
  for (std::size_t i = 1; i < order.size(); ++i) {
    const gi::Event& a = s.events[order[i - 1]];
    const gi::Event& b = s.events[order[i]];
    EXPECT_TRUE(a.first < b.first || (a.first == b.first && a.index < b.index));
  }
}

// ---- The schema and the parser list the same keys and enums.
TEST(ScenarioSchema, KeysAndEnumsMatchTheParser) {
  const json S = schema();
  const json& D = S["$defs"];
  const gi::ScenarioKeys& K = gi::scenario_keys();
  EXPECT_EQ(as_set(keys_of(S["properties"])), as_set(K.top_level));
  EXPECT_EQ(as_set(S["required"]), as_set(K.required_top_level));
  EXPECT_EQ(as_set(keys_of(D["scene"]["properties"])), as_set(K.scene_keys));
  EXPECT_EQ(as_set(keys_of(D["camera"]["properties"])), as_set(K.camera_keys));
  EXPECT_EQ(as_set(keys_of(D["camera_key"]["properties"])), as_set(K.camera_key_keys));
  EXPECT_EQ(as_set(keys_of(D["camera_pose"]["properties"])), as_set(K.camera_pose_keys));
  EXPECT_EQ(as_set(keys_of(D["mesh_generator"]["properties"])), as_set(K.mesh_generator_keys));
  EXPECT_EQ(as_set(keys_of(D["event_spawn"]["properties"]["repeat"]["properties"])), as_set(K.spawn_repeat_keys));
  EXPECT_EQ(as_set(keys_of(D["cornell_box_params"]["properties"])), as_set(K.cornell_box_params));
  EXPECT_EQ(as_set(keys_of(D["cliff_params"]["properties"])), as_set(K.cliff_params));
  EXPECT_EQ(as_set(S["properties"]["mode"]["enum"]), as_set(K.modes));
  EXPECT_EQ(as_set(S["properties"]["profile"]["enum"]), as_set(K.profiles));
  EXPECT_EQ(as_set(D["event"]["properties"]["type"]["enum"]), as_set(K.event_types));
  EXPECT_EQ(K.event_keys.size(), K.event_types.size());
  for (const std::string& t : K.event_types) {
    SCOPED_TRACE(t);
    ASSERT_TRUE(D.contains("event_" + t));
    EXPECT_EQ(D["event_" + t]["properties"]["type"]["const"], t);
    EXPECT_EQ(D["event_" + t]["additionalProperties"], false);
    EXPECT_EQ(as_set(keys_of(D["event_" + t]["properties"])), as_set(K.event_keys.at(t)));
  }
  EXPECT_EQ(as_set(D["check"]["properties"]["name"]["enum"]), as_set(K.check_names));
  std::set<std::string> fixed;
  for (auto it = D.begin(); it != D.end(); ++it)
    if (it.key().rfind("check_", 0) == 0) fixed.insert(it.key().substr(6));
  std::set<std::string> parser_fixed;
  for (const auto& [name, keys] : K.check_keys) {
    parser_fixed.insert(name);
    EXPECT_EQ(as_set(keys_of(D["check_" + name]["properties"])), as_set(keys)) << name;
  }
  EXPECT_EQ(fixed, parser_fixed);
}

// ---- The schema's check part is written from the checks' own files
// (`giharness schema`): a check that changed its parameters without the
// schema being written again fails here.
TEST(ScenarioSchema, ChecksPartIsWrittenFromTheChecksOwnFiles) {
  std::ifstream in(kSource / "scenarios/schema.json", std::ios::binary);
  std::stringstream committed;
  committed << in.rdbuf();
  const nlohmann::ordered_json schema = nlohmann::ordered_json::parse(committed.str());
  EXPECT_EQ(gi::with_declared_checks(schema).dump(2, ' ', false) + "\n", committed.str())
      << "run: build/giharness schema --out scenarios/schema.json";
}

// ---- Verdicts: every scenario file, and mutations of the good ones, are
// accepted by the parser exactly when the schema accepts them (except the
// files whose error needs more than the document).
TEST(ScenarioSchema, ParserAndSchemaAgreeOnEveryFile) {
  const SchemaValidator v(schema());
  const std::set<std::string> beyond_schema = {"missing_scene_file.json", "unknown_light_name.json",
                                               "unknown_generator.json", "unknown_mesh_generator.json",
                                               // what the canvas or the pipeline decides
                                               "rc_spawn_event.json",
                                               "rc_light_on_occluder.json", "rc_bad_shape.json", "rc_solari_key.json"};
  const std::set<std::string> guarded = {"duplicate_key.json", "byte_order_mark.json", "deep_nesting.json",
                                         "number_overflow.json"};
  int n = 0;
  for (const fs::path& f : scenario_files()) {
    SCOPED_TRACE(f.string());
    json doc;
    // Faults below the document (a duplicate key, a BOM, depth, a number past
    // a double) are the guarded reader's, not the schema's: nlohmann alone
    // reads some of them without complaint.
    if (guarded.count(f.filename().string())) {
      EXPECT_THROW(gi::load_scenario(f), gi::InputError);
      continue;
    }
    try {
      std::ifstream in(f);
      doc = json::parse(in);
    } catch (const json::exception&) {
      EXPECT_THROW(gi::load_scenario(f), gi::InputError);
      continue;
    }
    ++n;
    const bool schema_ok = v.valid(doc);
    const bool parser_ok = parser_accepts(doc, f);
    if (beyond_schema.count(f.filename().string())) {
      EXPECT_TRUE(schema_ok);
    } else {
      EXPECT_EQ(schema_ok, parser_ok);
    }
    if (f.parent_path() == kBad && !beyond_schema.count(f.filename().string())) {
      EXPECT_FALSE(parser_ok);
    }
  }
  EXPECT_GE(n, 10);
}

TEST(ScenarioSchema, ParserAndSchemaAgreeOnMutations) {
  const SchemaValidator v(schema());
  const gi::ScenarioKeys& K = gi::scenario_keys();
  int n = 0;
  auto agree = [&](const json& doc, const fs::path& f, const std::string& what) {
    ++n;
    EXPECT_EQ(v.valid(doc), parser_accepts(doc, f)) << what << "\n" << doc.dump();
  };
  for (const fs::path& f : {kSource / "scenarios/cornell_box.json", kGood / "all_events.json"}) {
    SCOPED_TRACE(f.string());
    const json base = read_json(f);
    agree(base, f, "as is");
    // An unknown key in every object the format defines.
    std::vector<std::string> objects = {"", "/scene"};
    if (base.contains("camera")) objects.push_back("/camera");
    for (std::size_t i = 0; i < base.value("events", json::array()).size(); ++i) {
      objects.push_back("/events/" + std::to_string(i));
      if (base["events"][i].contains("keys")) objects.push_back("/events/" + std::to_string(i) + "/keys/0");
      if (base["events"][i].contains("from")) objects.push_back("/events/" + std::to_string(i) + "/from");
    }
    for (std::size_t i = 0; i < base.value("checks", json::array()).size(); ++i)
      if (K.check_keys.count(base["checks"][i]["name"])) objects.push_back("/checks/" + std::to_string(i));
    for (const std::string& o : objects) {
      json doc = base;
      doc[json::json_pointer(o)]["zz_unknown"] = 1;
      agree(doc, f, "unknown key in " + o);
      EXPECT_FALSE(parser_accepts(doc, f)) << o;
    }
    // Every event re-typed as every other type; every check renamed.
    for (std::size_t i = 0; i < base.value("events", json::array()).size(); ++i)
      for (const std::string& t : K.event_types) {
        json doc = base;
        doc["events"][i]["type"] = t;
        agree(doc, f, "event " + std::to_string(i) + " as " + t);
        doc["events"][i].erase("frame");
        agree(doc, f, "event " + std::to_string(i) + " as " + t + " without frame");
      }
    for (std::size_t i = 0; i < base.value("checks", json::array()).size(); ++i)
      for (const std::string& c : K.check_names) {
        json doc = base;
        doc["checks"][i]["name"] = c;
        bool repeated = false;  // uniqueness of names is beyond the schema
        for (std::size_t j = 0; j < doc["checks"].size(); ++j) repeated = repeated || (j != i && doc["checks"][j]["name"] == c);
        if (repeated) {
          EXPECT_FALSE(parser_accepts(doc, f));
          continue;
        }
        agree(doc, f, "check " + std::to_string(i) + " as " + c);
      }
    // Removing each top-level key; out-of-range and wrong-typed values.
    for (auto it = base.begin(); it != base.end(); ++it) {
      json doc = base;
      doc.erase(it.key());
      agree(doc, f, "without " + it.key());
    }
    const std::pair<const char*, json> values[] = {
        {"/frames", 0}, {"/frames", 10000000}, {"/frames", 10000001}, {"/frames", -1}, {"/frames", 1.5},
        {"/resolution", json::array({0, 1})}, {"/resolution", json::array({8192, 8192})},
        {"/resolution", json::array({1, 2, 3})}, {"/seed", 4294967295u}, {"/seed", 4294967296u},
        {"/profile", "solari-0.19"}, {"/mode", "fast"}, {"/samples_per_frame", 1025}, {"/name", "Bad Name"},
        {"/scene", json{{"gltf", "x.gltf"}, {"generator", "cornell_box"}}}, {"/scene/params/albedo_scale", 2},
        {"/capture", json::array({1, 1})}, {"/overrides", json::array()}, {"/events", json::object()}};
    for (const auto& [ptr, value] : values) {
      json doc = base;
      doc[json::json_pointer(ptr)] = value;
      if (std::string(ptr) == "/scene/params/albedo_scale") {
        // Generator params are checked by build_scene, not the parser.
        EXPECT_FALSE(v.valid(doc));
        EXPECT_THROW(gi::build_scene(gi::parse_scenario(doc, f)), gi::InputError);
        continue;
      }
      agree(doc, f, std::string(ptr) + " = " + value.dump());
    }
  }
  EXPECT_GT(n, 100);
}
