// The timing verdicts in the nightly's outputs: the suite's tally
// and exit bit, the report's tables with each timing's interval, and the
// history of past nights that the report draws the trend from.
//
// History: with `nightly --history DIR`, each night leaves DIR/<UTC time>.json,
// a small summary (per scenario: its verdict, its timing verdict and the
// pipeline total's ratio to the baseline with its interval and ms). The
// report reads the newest `nights` of them before writing its own.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/gnuplot.h"

namespace gi {

// A timing regression's bit in the exit code, set only when the suite asks
// for timing to be fatal (`--fail-on-timing`); correctness keeps 0-3.
inline constexpr int kTimingExitBit = 4;

// {"regressed", "improved", "unchanged", "not_compared", "loaded" (of those not compared, for load),
// "scenarios_regressed": [...], "fatal"} over the rows.
nlohmann::json timing_tally(const nlohmann::json& suite);

// Per scenario: one row per timed series (pass, baseline ms, measured ms,
// ratio, interval, verdict), for the report.
std::string timing_section(const nlohmann::json& timing);
// The suite's regressed and improved series, one table row each.
std::vector<std::vector<std::string>> timing_overview_rows(const nlohmann::json& suite);
extern const std::vector<std::string> kTimingOverviewHeader;

// "2026-12-03T16:40:05.123Z": a history entry's time and (sorted) file name;
// milliseconds, so two short nights in one second keep two entries.
std::string utc_timestamp();

// Reads the newest `nights` history entries into suite["timing_history"]
// before the report is written, and after it (finish_suite) adds this night's
// (`nightly` and `merge` with --history).
void attach_timing_history(nlohmann::json& suite, const std::filesystem::path& dir, std::size_t nights);
void record_timing_history(const nlohmann::json& suite, const std::filesystem::path& dir, const std::string& started_utc);

// This night as a history entry, and the newest `nights` entries of a folder
// (oldest first; none when the folder is absent).
nlohmann::json timing_history_entry(const nlohmann::json& suite, const std::string& started_utc);
nlohmann::json read_timing_history(const std::filesystem::path& dir, std::size_t nights);
void write_timing_history(const std::filesystem::path& dir, const nlohmann::json& entry);

// The pipeline total's ratio to the baseline per scenario over the history
// and this night (x: night number, 1 the oldest shown).
Plot timing_trend_plot(const nlohmann::json& history, const nlohmann::json& tonight);

}  // namespace gi
