// Finishing a suite (nightly, merge): the exit code from the rows, then
// summary.json, JUnit XML and the HTML report, all written atomically.
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

namespace gi {

// The worst row exit code (0 pass, 1 failed check or regression, 2 bad input,
// 3 device/internal); 3 also when the suite was interrupted (it is incomplete).
// Plus kTimingExitBit (4) when the suite has "fail_on_timing" and a scenario's
// timing regressed (so 4: only timing, 5: a check failed and timing too).
int suite_exit_code(const nlohmann::json& suite);

// Sets exit_code, verdict and the change tally ("changes"), writes <out>/summary.json, the JUnit XML (at
// `junit`, default <out>/junit.xml) and <out>/report.html. Returns the exit code.
int finish_suite(const std::filesystem::path& out_dir, nlohmann::json& suite, const std::filesystem::path& junit = {});

}  // namespace gi
