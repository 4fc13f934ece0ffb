// Every change visible (the nightly's third status beside pass and
// regression). The harness is bit-deterministic per device and thread count,
// so a baseline written on the same device and driver is exact: it keeps the
// output image's hash per frame, every state buffer's hash after the last
// frame, and the final image (half-float EXR). A run then is
//
// - unchanged: every hash equal (costs a string compare);
// - changed: some hash differs. The record says the first frame whose image
//   hash differs, which buffers differ, and, against the baseline image,
//   relMSE and energy ratio with a difference heat map beside both images;
// - no_exact_baseline: no baseline, one written before hashes were kept, or
//   one from another device class, device or driver (its hashes say nothing
//   about this device's bits). Never reported as changed.
//
// A change is not a failure unless the nightly runs with --fail-on-change
// (for a commit that must not change pixels, e.g. a refactor).
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.h"

namespace gi {

// The run's final image beside its summary.json, and a baseline's beside its JSON.
inline constexpr const char* kFinalImageFile = "final_image.exr";

// The output of one image against another (both linear RGB, same size).
struct ImageDifference {
  double relmse = 0;           // core/metrics.h relmse(current, baseline)
  double energy_ratio = 1;     // mean luminance of current over baseline
  double max_abs = 0;          // the largest |current − baseline| over pixels and channels
  std::size_t pixels_differing = 0;
  double heat_scale = 0;       // the luminance difference drawn at full heat (99.5th percentile)
};
ImageDifference image_difference(const Image& baseline, const Image& current);

// A heat map of |Δ luminance| per pixel: black at 0, through red and yellow
// to white at `scale` and above; magenta marks a non-finite pixel.
void write_difference_png(const std::filesystem::path& path, const Image& baseline, const Image& current,
                          double scale);

struct ChangeInputs {
  std::optional<nlohmann::json> baseline;         // the baseline's JSON document, if any
  std::filesystem::path baseline_image;           // its final image (may not exist)
  nlohmann::json summary;                         // the run's summary.json
  std::filesystem::path run_dir;                  // where that summary.json lies
  std::filesystem::path evidence_dir;             // where to write the PNGs of a change
  std::filesystem::path evidence_rel;             // evidence_dir relative to the suite's out dir
};

// The row's "change" record: {"status", "reason" | "first_differing_frame",
// "frames_compared", "differing_buffers", "buffers_compared", "image"{...},
// "images"{"baseline","current","difference"}}.
nlohmann::json detect_change(const ChangeInputs& in);

// The one key that says whether two device records produce the same bits:
// device class (driver and lavapipe threads), device name and driver version.
// Empty when they match, else what differs.
std::string exactness_mismatch(const nlohmann::json& baseline_device, const nlohmann::json& run_device);

}  // namespace gi
