// JUnit XML of a nightly (docs/design.md §10) for CI dashboards: one <testcase> per
// scenario × check (classname = scenario, name = check), one more per
// scenario named "baseline" for the figures no check owns (timings, per-frame
// curves), a failed case carrying each regression's metric, baseline,
// measured value and tolerance. A scenario that could not run (bad input,
// device error) is one case "run" with an <error>; one not reached (an
// interrupted or resumed night) is one case "run" marked <skipped>.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace gi {

// From the suite summary.json that app/nightly.cpp writes.
std::string junit_xml(const nlohmann::json& suite_summary);

std::string xml_escape(const std::string& text);

}  // namespace gi
