#include "tests/fuzz/fuzz_targets.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/gltf_import.h"
#include "core/scenario.h"
#include "core/scene_builder.h"
#include "tests/test_support.h"

namespace gi::fuzz {

void scenario_input(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded()) return;  // load_scenario turns this into an InputError; tested elsewhere
  try {
    const Scenario scenario = parse_scenario(doc, "fuzz.json");
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
