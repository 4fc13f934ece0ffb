// Baselines on disk: <root>/<device class>/<scenario>.json, one file per
// scenario holding its figures and check verdicts (reports/figures.h) and the
// hashes change detection compares (reports/change.h), beside
// <scenario>.exr, its final image in half floats; plus an optional
// <root>/<device class>/tolerances.json (reports/regression.h).
// Committed under reports/baselines/; `giharness baseline update` and
// `nightly --update-baseline` write them.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/figures.h"

namespace gi {

std::filesystem::path baseline_file(const std::filesystem::path& class_dir, const std::string& scenario);

// A baseline document's figures; `file` names it in the error when they are malformed.
ScenarioFigures baseline_figures(const nlohmann::json& doc, const std::filesystem::path& file);

// The whole baseline document (figures, verdicts, device, hashes), or nothing.
std::optional<nlohmann::json> read_baseline_document(const std::filesystem::path& class_dir,
                                                     const std::string& scenario);
std::filesystem::path baseline_image_file(const std::filesystem::path& class_dir, const std::string& scenario);

// Writes (atomically) the baseline of one scenario from its summary.json and
// copies the run's final image (in `run_dir`) beside it.
void write_baseline(const std::filesystem::path& class_dir, const nlohmann::json& scenario_summary,
                    const std::filesystem::path& run_dir);

// Adds the timing medians of another run of the same tree to a scenario's
// baseline (`nightly --add-timing-run`; reports/timing_verdict.h, "Run-to-run
// spread"), keeping the newest kTimingRunsKept - 1. Returns why it did not:
// no baseline, no timing samples, another unit, or a loaded run; "" when added.
std::string add_timing_run(const std::filesystem::path& class_dir, const nlohmann::json& scenario_summary);

// The default suite's baseline images must stay small enough to commit.
inline constexpr double kDefaultImageBudgetMb = 20.0;

// Keeps the images of a device class folder within `budget_mb`: while their
// total is over it, the largest image is dropped (its baseline JSON then says
// so under "image_dropped"; the hashes stay, so a change is still detected
// exactly, only without its relMSE and heat map). Returns the images' total
// bytes afterwards and the scenarios whose images were dropped.
struct ImageBudget {
  std::uintmax_t bytes = 0;
  std::vector<std::string> dropped;
};
ImageBudget enforce_image_budget(const std::filesystem::path& class_dir, double budget_mb);

}  // namespace gi
