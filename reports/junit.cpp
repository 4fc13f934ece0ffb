#include "reports/junit.h"

#include <algorithm>

#include <fmt/format.h>

#include "reports/seed_verdicts.h"

namespace gi {
namespace {

std::string figure_text(const nlohmann::json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

std::string describe(const nlohmann::json& r) {
  return fmt::format("{} {}: baseline {}, measured {}, tolerance {}", r.value("metric", "?"), r.value("status", "?"),
                     figure_text(r.value("baseline", nlohmann::json())),
                     figure_text(r.value("measured", nlohmann::json())), r.value("tolerance", ""));
}

struct Case {
  std::string classname, name, failure, failure_text, error, skipped;
  double seconds = 0;
  std::vector<std::pair<std::string, std::string>> properties;
};

std::string render(const Case& c) {
  std::string out = fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{:.3f}\"", xml_escape(c.classname),
                                xml_escape(c.name), c.seconds);
  if (c.failure.empty() && c.error.empty() && c.skipped.empty() && c.properties.empty()) return out + "/>\n";
  out += ">\n";
  if (!c.properties.empty()) {
    out += "      <properties>\n";
    for (const auto& [name, value] : c.properties)
      out += fmt::format("        <property name=\"{}\" value=\"{}\"/>\n", xml_escape(name), xml_escape(value));
    out += "      </properties>\n";
  }
  if (!c.failure.empty())
    out += fmt::format("      <failure message=\"{}\">{}</failure>\n", xml_escape(c.failure), xml_escape(c.failure_text));
  if (!c.error.empty()) out += fmt::format("      <error message=\"{}\"/>\n", xml_escape(c.error));
  if (!c.skipped.empty()) out += fmt::format("      <skipped message=\"{}\"/>\n", xml_escape(c.skipped));
  return out + "    </testcase>\n";
}

// Speed apart from correctness (reports/timing_verdict.h): properties with
// each judged series' ratio and interval; a failure only when the suite makes
// timing fatal (--fail-on-timing), so a slow machine never reads as a bug.
Case timing_case(const std::string& scenario, const nlohmann::json& timing, bool fatal) {
  Case t{scenario, "timing", "", "", "", "", 0, {}};
  const std::string verdict = timing.value("verdict", "not_compared");
  t.properties.push_back({"timing_verdict", verdict});
  t.properties.push_back({"timing_unit", timing.value("unit", "")});
  if (verdict == "not_compared") t.skipped = "timing not compared: " + timing.value("reason", "");
  for (const nlohmann::json& s : timing.value("series", nlohmann::json::array())) {
    const std::string v = s.value("verdict", "");
    if (v != "regressed" && v != "improved" && s.value("name", "") != "pipeline_total") continue;
    const std::string text = fmt::format("{} {}: ratio {} interval {} ({} ms against {} ms)", s.value("name", "?"), v,
                                         figure_text(s.value("ratio", nlohmann::json())),
                                         s.value("interval", nlohmann::json::array()).dump(),
                                         figure_text(s.value("measured_ms", nlohmann::json())),
                                         figure_text(s.value("baseline_ms", nlohmann::json())));
    t.properties.push_back({"timing/" + s.value("name", "?"), text});
    if (v == "regressed" && fatal) {
      if (t.failure.empty()) t.failure = "timing regressed (--fail-on-timing): " + text;
      t.failure_text += text + "\n";
    }
  }
  return t;
}

}  // namespace

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // XML 1.0 forbids most control characters even escaped.
        if (static_cast<unsigned char>(ch) < 0x20 && ch != '\n' && ch != '\t' && ch != '\r') out += '?';
        else out += ch;
    }
  }
  return out;
}

std::string junit_xml(const nlohmann::json& suite) {
  std::vector<Case> cases;
  for (const nlohmann::json& row : suite.value("scenarios", nlohmann::json::array())) {
    const std::string scenario = row.value("name", row.value("file", "?"));
    const nlohmann::json wall = row.value("wall_seconds", nlohmann::json(0.0));
    const double seconds = wall.is_number() ? wall.get<double>() : 0.0;
    const std::string status = row.value("status", "complete");
    if (status != "complete") {
      cases.push_back({scenario, "run", "", "", "", "not run: " + status, 0, {}});
      continue;
    }
    if (row.contains("error")) {
      cases.push_back({scenario, "run", "", "", row["error"].get<std::string>(), "", seconds, {}});
      continue;
    }
    const nlohmann::json regressions = row.value("regressions", nlohmann::json::array());
    std::vector<bool> attributed(regressions.size(), false);
    const nlohmann::json checks = row.value("checks", nlohmann::json::array());
    // A bug-museum scenario: its catching checks must fail, and one that
    // passes is the failure; its other checks only inform (the row's verdict
    // is caught or missed, app/nightly.cpp).
    const nlohmann::json bug = row.value("bug", nlohmann::json());
    auto catches = [&](const std::string& check) {
      if (!bug.is_object()) return false;
      for (const nlohmann::json& n : bug.value("caught_by", nlohmann::json::array()))
        if (n == check) return true;
      return false;
    };
    // Seeds as a dimension (reports/seed_verdicts.h): the check's verdict at
    // each seed; "message" and "limits" are seed 0's.
    const nlohmann::json seed_values = row.value("seeds", nlohmann::json::object()).value("values", nlohmann::json::array());
    for (const nlohmann::json& c : checks) {
      Case k{scenario, c.value("name", "?"), "", "", "", "", seconds / double(checks.size() + 1), {}};
      const bool seeded = c.contains("seed_verdicts") && c["seed_verdicts"].is_array() && seed_values.is_array();
      std::vector<std::string> verdicts;
      std::string per_seed;
      if (seeded) {
        verdicts = c["seed_verdicts"].get<std::vector<std::string>>();
        per_seed = seed_verdict_list(seed_values.get<std::vector<std::uint32_t>>(), verdicts, verdicts.size());
        k.properties.push_back({"seed_status", c.value("seed_status", "")});
        k.properties.push_back({"seed_verdicts", per_seed});
      }
      const std::size_t passed_at = std::count(verdicts.begin(), verdicts.end(), std::string("pass"));
      const bool failed = seeded ? c.value("seed_status", "fail") != "pass" : c.value("verdict", "fail") != "pass";
      if (catches(k.name)) {
        k.properties.push_back({"bug", bug.value("source", "")});
        if (seeded && passed_at > 0) {
          k.failure = fmt::format("missed bug {} at {} of {} seeds: {} passed ({})", bug.value("source", ""), passed_at,
                                  verdicts.size(), k.name, per_seed);
          k.failure_text = "the check should fail on this re-created bug at every seed: " + bug.value("symptom", "") + "\n";
        } else if (!seeded && !failed) {
          k.failure = fmt::format("missed bug {}: {} passed ({})", bug.value("source", ""), k.name, c.value("message", ""));
          k.failure_text = "the check should fail on this re-created bug: " + bug.value("symptom", "") + "\n";
        }
      } else if (bug.is_object()) {
        k.properties.push_back({"verdict", c.value("verdict", "fail")});  // the bug's other checks only inform
      } else if (failed && seeded && c.value("seed_status", "") == "flaky") {
        k.failure = fmt::format("flaky: passed at {} of {} seeds: {}", passed_at, verdicts.size(), per_seed);
        k.failure_text = "seed 0: " + c.value("verdict", "fail") + ": " + c.value("message", "") +
                         "\nlimits: " + c.value("limits", nlohmann::json::object()).dump() + "\n";
      } else if (failed) {
        k.failure = fmt::format("{}: {}", seeded ? c.value("seed_status", "fail") : c.value("verdict", "fail"),
                                c.value("message", ""));
        if (seeded) k.failure += " (" + per_seed + ")";
        k.failure_text = "limits: " + c.value("limits", nlohmann::json::object()).dump() + "\n";
      }
      const std::string prefix = "checks/" + k.name + "/";
      for (std::size_t i = 0; i < regressions.size(); ++i) {
        const nlohmann::json& r = regressions[i];
        if (r.value("metric", "").rfind(prefix, 0) != 0) continue;
        attributed[i] = true;
        if (k.failure.empty()) k.failure = "regression: " + describe(r);
        k.failure_text += describe(r) + "\n";
      }
      cases.push_back(k);
    }
    const std::string comparison = row.value("baseline_status", "no_baseline");
    Case b{scenario, "baseline", "", "", "", "", seconds / double(checks.size() + 1), {}};
    if (comparison != "compared") b.skipped = "no baseline for this scenario and device class";
    for (std::size_t i = 0; i < regressions.size(); ++i) {
      if (attributed[i]) continue;
      if (b.failure.empty()) b.failure = "regression: " + describe(regressions[i]);
      b.failure_text += describe(regressions[i]) + "\n";
    }
    // Bits against the exact baseline (reports/change.h): properties, and a
    // failure only under --fail-on-change.
    if (row.contains("change")) {
      const nlohmann::json& c = row["change"];
      b.properties.push_back({"change", c.value("status", "no_exact_baseline")});
      if (c.contains("reason")) b.properties.push_back({"change_reason", c["reason"].get<std::string>()});
      if (c.value("status", "") == "changed") {
        const nlohmann::json image = c.value("image", nlohmann::json());
        b.properties.push_back({"change_first_differing_frame", figure_text(c.value("first_differing_frame", nlohmann::json()))});
        b.properties.push_back({"change_differing_buffers", c.value("differing_buffers", nlohmann::json::array()).dump()});
        if (image.is_object()) {
          b.properties.push_back({"change_relmse", figure_text(image.value("relmse", nlohmann::json()))});
          b.properties.push_back({"change_energy_ratio", figure_text(image.value("energy_ratio", nlohmann::json()))});
        }
        if (c.value("fails", false)) {
          b.skipped.clear();
          if (b.failure.empty()) b.failure = "changed against the exact baseline (--fail-on-change)";
          b.failure_text += "changed: first differing frame " + figure_text(c.value("first_differing_frame", nlohmann::json())) +
                            ", differing buffers " + c.value("differing_buffers", nlohmann::json::array()).dump() + "\n";
        }
      }
    }
    cases.push_back(b);
    if (row.contains("timing")) cases.push_back(timing_case(scenario, row["timing"], suite.value("fail_on_timing", false)));
  }
  std::size_t failures = 0, errors = 0, skipped = 0;
  double total = 0;
  for (const Case& c : cases) {
    failures += !c.failure.empty();
    errors += !c.error.empty();
    skipped += !c.skipped.empty();
    total += c.seconds;
  }
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += fmt::format("<testsuites name=\"giharness nightly\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\" time=\"{:.3f}\">\n",
                     cases.size(), failures, errors, skipped, total);
  out += fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\" time=\"{:.3f}\">\n",
                     xml_escape(suite.value("suite", "suite")), cases.size(), failures, errors, skipped, total);
  for (const Case& c : cases) out += render(c);
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

}  // namespace gi
