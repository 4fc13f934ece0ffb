// Check results are data (docs/design.md §6): name, verdict, measured figure, limit,
// first failing frame, and the buffers that show it.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

enum class Verdict {
  pass,
  fail,
  // The measurement cannot decide: e.g. the reference's own noise is not far
  // enough below the tolerance. Never counted as a pass (exit code 1).
  inconclusive,
};

const char* to_string(Verdict v);

struct CheckResult {
  std::string name;
  Verdict verdict = Verdict::fail;
  std::string message;                  // one line a person reads first
  nlohmann::json figures = nlohmann::json::object();  // measured values, by name
  nlohmann::json limits = nlohmann::json::object();   // the tolerances they were held to
  std::optional<std::uint32_t> first_failing_frame;
  std::vector<std::string> evidence;    // files (relative to the run's out dir) that show it
  // The image region the verdict judged, at first_failing_frame (else the
  // frame the message names), for a check that judges a region: [x0, y0, x1,
  // y1] inclusive pixels (null for the whole image), and where it wrote the
  // region's mask {"file": evidence file, "layer": EXR layer, 1 inside}. The
  // nightly's failure capture carries both to the inspector, which outlines them.
  nlohmann::json region;
  nlohmann::json region_mask;

  bool passed() const { return verdict == Verdict::pass; }
  // `limits` with the declared check's false-alarm rate (CheckModel) added:
  // every summary, report and JUnit case states the rate of its verdict.
  nlohmann::json stated_limits() const;
  nlohmann::json to_json() const;
};

// The bounding box of a mask's set pixels, [x0, y0, x1, y1] inclusive (row
// major, `width` a row), or null when none is set: CheckResult::region.
nlohmann::json mask_bounds(const std::vector<bool>& mask, std::uint32_t width);

}  // namespace gi
