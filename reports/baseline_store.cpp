#include "reports/baseline_store.h"

#include <fstream>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace gi {

std::filesystem::path baseline_file(const std::filesystem::path& class_dir, const std::string& scenario) {
  return class_dir / (scenario + ".json");
}

std::optional<ScenarioFigures> read_baseline(const std::filesystem::path& class_dir, const std::string& scenario) {
  const std::filesystem::path file = baseline_file(class_dir, scenario);
  if (!std::filesystem::exists(file)) return std::nullopt;
  try {
    return ScenarioFigures::from_json(nlohmann::json::parse(std::ifstream(file)));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string(), "", std::string("a baseline with \"figures\" and \"verdicts\" (") + e.what() + ")");
  }
}

void write_baseline(const std::filesystem::path& class_dir, const nlohmann::json& s) {
  const std::string name = s.at("scenario").at("name");
  nlohmann::json doc = extract_figures(s).to_json();
  doc["scenario"] = name;
  doc["device_class"] = device_class(s.value("device", nlohmann::json::object()));
  doc["device"] = s.value("device", nlohmann::json::object());
  // What a reader needs to see the baseline ran the same configuration; the
  // full resolved profile stays in the run's summary.json.
  const nlohmann::json resolved = s.value("resolved", nlohmann::json::object());
  doc["resolved"] = nlohmann::json::object();
  for (const char* key : {"resolution", "frames", "seed", "mode", "samples_per_frame", "profile", "overrides", "backend"})
    if (resolved.contains(key)) doc["resolved"][key] = resolved[key];
  doc["final_image_hash"] = s.value("final_image_hash", "");
  write_json_file(baseline_file(class_dir, name), doc);
}

}  // namespace gi
