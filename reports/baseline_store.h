// Baselines on disk: <root>/<device class>/<scenario>.json, one file per
// scenario holding its figures and check verdicts (reports/figures.h), plus an
// optional <root>/<device class>/tolerances.json (reports/regression.h).
// Committed under reports/baselines/; `giharness baseline update` and
// `nightly --update-baseline` write them.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "reports/figures.h"

namespace gi {

std::filesystem::path baseline_file(const std::filesystem::path& class_dir, const std::string& scenario);

// The scenario's baseline, or nothing when the file does not exist.
// InputError naming the file when it exists but is malformed.
std::optional<ScenarioFigures> read_baseline(const std::filesystem::path& class_dir, const std::string& scenario);

// Writes (atomically) the baseline of one scenario from its summary.json.
void write_baseline(const std::filesystem::path& class_dir, const nlohmann::json& scenario_summary);

}  // namespace gi
