#include "reports/baseline_store.h"

#include <algorithm>
#include <functional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/json_input.h"
#include "reports/change.h"
#include "reports/timing_verdict.h"

namespace gi {

std::filesystem::path baseline_file(const std::filesystem::path& class_dir, const std::string& scenario) {
  return class_dir / (scenario + ".json");
}

std::filesystem::path baseline_image_file(const std::filesystem::path& class_dir, const std::string& scenario) {
  return class_dir / (scenario + ".exr");
}

std::optional<nlohmann::json> read_baseline_document(const std::filesystem::path& class_dir,
                                                     const std::string& scenario) {
  const std::filesystem::path file = baseline_file(class_dir, scenario);
  if (!std::filesystem::exists(file)) return std::nullopt;
  return read_json_input(file, "a baseline");
}

ScenarioFigures baseline_figures(const nlohmann::json& doc, const std::filesystem::path& file) {
  try {
    return ScenarioFigures::from_json(doc);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string(), "", std::string("a baseline with \"figures\" and \"verdicts\" (") + e.what() + ")");
  }
}

void write_baseline(const std::filesystem::path& class_dir, const nlohmann::json& s,
                    const std::filesystem::path& run_dir) {
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
  // Per-frame pass times for the timing verdicts (reports/timing_verdict.h).
  const TimingSamples samples = timing_samples(s);
  if (!samples.series.empty() || samples.loaded_frames > 0) doc["timing_samples"] = samples.to_json();
  if (samples.loaded_frames > 0 && samples.frames - samples.loaded_frames < TimingPolicy{}.min_samples)
    spdlog::warn("baseline {}: the machine was loaded ({} of {} timed frames waited for a CPU, median {:.0f} % of the "
                 "time they wanted one): no timing verdict can use it; retake it on a quiet machine",
                 name, samples.loaded_frames, samples.frames, 100 * samples.median_wait_share);
  doc["final_image_hash"] = s.value("final_image_hash", "");
  if (s.contains("hashes")) doc["hashes"] = s["hashes"];
  const std::filesystem::path image = run_dir / s.value("final_image", kFinalImageFile);
  if (std::filesystem::exists(image)) {
    std::filesystem::create_directories(class_dir);
    write_atomically(baseline_image_file(class_dir, name), [&](const std::filesystem::path& tmp) {
      std::filesystem::copy_file(image, tmp, std::filesystem::copy_options::overwrite_existing);
    });
    doc["image"] = baseline_image_file(class_dir, name).filename().string();
  } else {
    std::error_code ec;
    std::filesystem::remove(baseline_image_file(class_dir, name), ec);  // never an image of another run
  }
  write_json_file(baseline_file(class_dir, name), doc);
}

std::string add_timing_run(const std::filesystem::path& class_dir, const nlohmann::json& s) {
  const std::string name = s.at("scenario").at("name");
  std::optional<nlohmann::json> doc = read_baseline_document(class_dir, name);
  if (!doc) return "no baseline";
  if (!doc->contains("timing_samples")) return "the baseline has no timing samples";
  const std::filesystem::path file = baseline_file(class_dir, name);
  TimingSamples base = TimingSamples::from_json((*doc)["timing_samples"], file.string());
  const TimingSamples run = timing_samples(s);
  if (run.unit != base.unit) return "the run's samples are in " + run.unit + ", the baseline's in " + base.unit;
  if (run.series.empty() || run.loaded(TimingPolicy{}.min_samples)) return "the run was loaded or kept no timed frames";
  base.other_runs.push_back(run.medians());
  if (base.other_runs.size() >= kTimingRunsKept)
    base.other_runs.erase(base.other_runs.begin(), base.other_runs.end() - std::ptrdiff_t(kTimingRunsKept - 1));
  (*doc)["timing_samples"] = base.to_json();
  write_json_file(file, *doc);
  return "";
}

ImageBudget enforce_image_budget(const std::filesystem::path& class_dir, double budget_mb) {
  ImageBudget out;
  if (!std::filesystem::is_directory(class_dir)) return out;
  std::vector<std::pair<std::uintmax_t, std::filesystem::path>> images;
  for (const auto& entry : std::filesystem::directory_iterator(class_dir))
    if (entry.is_regular_file() && entry.path().extension() == ".exr") {
      images.emplace_back(entry.file_size(), entry.path());
      out.bytes += entry.file_size();
    }
  std::sort(images.begin(), images.end(), std::greater<>());
  const double budget = budget_mb * 1024 * 1024;
  for (const auto& [bytes, path] : images) {
    if (double(out.bytes) <= budget) break;
    const std::string scenario = path.stem().string();
    const std::filesystem::path json = baseline_file(class_dir, scenario);
    if (std::filesystem::exists(json)) {
      nlohmann::json doc = read_json_input(json, "a baseline");
      doc.erase("image");
      doc["image_dropped"] = fmt::format("the images of {} exceeded the {} MB budget; the largest ({} bytes) went first",
                                         class_dir.string(), budget_mb, bytes);
      write_json_file(json, doc);
    }
    std::filesystem::remove(path);
    out.bytes -= bytes;
    out.dropped.push_back(scenario);
  }
  return out;
}

}  // namespace gi
