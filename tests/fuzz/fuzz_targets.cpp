#include "tests/fuzz/fuzz_targets.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/json_input.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "tests/test_support.h"

namespace gi::fuzz {

void scenario_input(const std::uint8_t* data, std::size_t size) {
  // The guarded reader load_scenario uses (core/json_input.h): deep nesting,
  // huge numbers and duplicate keys are InputErrors, never crashes.
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const Scenario scenario = parse_scenario(parse_json_input(text, "fuzz.json"), "fuzz.json");
    if (scenario.scene.gltf.empty()) build_scene(scenario);
  } catch (const InputError&) {
  }
}

void gltf_input(const std::uint8_t* data, std::size_t size) {
  // One folder per process: buffers referenced by relative URI resolve (or
  // fail to) inside it, never in the working directory; removed at exit.
  static const test::TempDir tmp("fuzz");
  const std::filesystem::path& dir = tmp.path();
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::filesystem::path file = dir / (glb ? "input.glb" : "input.gltf");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    import_gltf(file);
  } catch (const InputError&) {
  }
}

}  // namespace gi::fuzz
