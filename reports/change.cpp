#include "reports/change.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "core/exr_io.h"
#include "core/metrics.h"
#include "core/png_preview.h"
#include "core/shared/word_hash.h"
#include "reports/figures.h"
#include "reports/json_figures.h"

namespace gi {
namespace {

double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// black → red → yellow → white over t in [0, 1].
glm::vec3 heat(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return {float(std::min(1.0, 3 * t)), float(std::clamp(3 * t - 1, 0.0, 1.0)), float(std::clamp(3 * t - 2, 0.0, 1.0))};
}

// The per-frame image hashes of both sides, aligned by frame number.
nlohmann::json compare_frames(const nlohmann::json& baseline, const nlohmann::json& current) {
  const std::uint32_t b0 = baseline.value("first_frame", 0u), c0 = current.value("first_frame", 0u);
  const nlohmann::json bf = baseline.value("frame_images", nlohmann::json::array());
  const nlohmann::json cf = current.value("frame_images", nlohmann::json::array());
  const std::uint32_t first = std::max(b0, c0);
  const std::uint32_t end = std::min<std::uint32_t>(b0 + std::uint32_t(bf.size()), c0 + std::uint32_t(cf.size()));
  nlohmann::json out = {{"frames_compared", end > first ? end - first : 0}, {"first_differing_frame", nullptr}};
  for (std::uint32_t f = first; f < end; ++f)
    if (bf[f - b0] != cf[f - c0]) {
      out["first_differing_frame"] = f;
      break;
    }
  if (bf.size() + b0 != cf.size() + c0) out["frame_count"] = {{"baseline", b0 + bf.size()}, {"current", c0 + cf.size()}};
  return out;
}

nlohmann::json compare_buffers(const nlohmann::json& baseline, const nlohmann::json& current) {
  const nlohmann::json b = baseline.value("final_buffers", nlohmann::json::object());
  const nlohmann::json c = current.value("final_buffers", nlohmann::json::object());
  nlohmann::json differing = nlohmann::json::array(), added = nlohmann::json::array(), removed = nlohmann::json::array();
  for (const auto& [name, hash] : c.items()) {
    if (!b.contains(name)) added.push_back(name);
    else if (b[name] != hash) differing.push_back(name);
  }
  for (const auto& [name, hash] : b.items())
    if (!c.contains(name)) removed.push_back(name);
  return {{"buffers_compared", c.size()}, {"differing_buffers", differing}, {"added_buffers", added},
          {"removed_buffers", removed}};
}

}  // namespace

ImageDifference image_difference(const Image& baseline, const Image& current) {
  if (baseline.width != current.width || baseline.height != current.height)
    throw std::invalid_argument(fmt::format("image_difference: {}x{} against {}x{}", current.width, current.height,
                                            baseline.width, baseline.height));
  ImageDifference d;
  d.relmse = relmse(current, baseline);
  d.energy_ratio = energy_ratio(current, baseline);
  std::vector<double> deltas;
  deltas.reserve(current.size());
  for (std::size_t i = 0; i < current.size(); ++i) {
    const glm::vec3 diff = glm::abs(current.pixels[i] - baseline.pixels[i]);
    const double m = std::max({diff.x, diff.y, diff.z});
    if (!(m == 0)) ++d.pixels_differing;  // NaN counts as differing
    if (std::isfinite(m)) d.max_abs = std::max(d.max_abs, m);
    const double dl = std::abs(luminance(current.pixels[i]) - luminance(baseline.pixels[i]));
    if (std::isfinite(dl)) deltas.push_back(dl);
  }
  // A percentile, not the maximum: one firefly would otherwise leave the rest black.
  if (!deltas.empty()) {
    const std::size_t k = std::min(deltas.size() - 1, std::size_t(std::floor(0.995 * double(deltas.size()))));
    std::nth_element(deltas.begin(), deltas.begin() + std::ptrdiff_t(k), deltas.end());
    d.heat_scale = deltas[k];
    if (d.heat_scale == 0) d.heat_scale = *std::max_element(deltas.begin(), deltas.end());
  }
  return d;
}

void write_difference_png(const std::filesystem::path& path, const Image& baseline, const Image& current,
                          double scale) {
  Image map(current.width, current.height);
  for (std::size_t i = 0; i < current.size(); ++i) {
    const double dl = std::abs(luminance(current.pixels[i]) - luminance(baseline.pixels[i]));
    // Linear values that write_png_preview's sRGB encoding turns back into the heat colours' intensities.
    const glm::vec3 c = std::isfinite(dl) ? heat(scale > 0 ? dl / scale : 0.0) : glm::vec3(1, 0, 1);
    map.pixels[i] = glm::pow(c, glm::vec3(2.2f));
  }
  write_png_preview(path, map);
}

std::string exactness_mismatch(const nlohmann::json& baseline_device, const nlohmann::json& run_device) {
  const std::string bc = device_class(baseline_device), rc = device_class(run_device);
  if (bc != rc) return fmt::format("the baseline is from device class {}, this run is {}", bc, rc);
  for (const char* key : {"name", "driver_info"}) {
    const std::string b = baseline_device.value(key, ""), r = run_device.value(key, "");
    if (b != r) return fmt::format("the baseline's device {} is \"{}\", this run's is \"{}\"", key, b, r);
  }
  return "";
}

nlohmann::json detect_change(const ChangeInputs& in) {
  const nlohmann::json& s = in.summary;
  if (!in.baseline) return {{"status", "no_exact_baseline"}, {"reason", "no baseline for this scenario"}};
  const nlohmann::json& base = *in.baseline;
  if (!s.contains("hashes"))
    return {{"status", "no_exact_baseline"},
            {"reason", "this run records no image or buffer hashes (no GPU pipeline ran: e.g. a count-only "
                       "cluster_ids scenario)"}};
  if (!base.contains("hashes"))
    return {{"status", "no_exact_baseline"},
            {"reason", "the baseline keeps no hashes (written before change detection; run `baseline update`)"}};
  // Before the GPU computed them, hashes were XXH3-64 of the same bytes.
  const std::string base_scheme = base["hashes"].value("scheme", shader::XXH3_HASH_SCHEME);
  const std::string run_scheme = s["hashes"].value("scheme", shader::XXH3_HASH_SCHEME);
  if (base_scheme != run_scheme)
    return {{"status", "no_exact_baseline"},
            {"reason", fmt::format("the baseline's hashes are {}, this run's {} (run `baseline update`)", base_scheme,
                                   run_scheme)}};
  const std::string mismatch = exactness_mismatch(base.value("device", nlohmann::json::object()),
                                                  s.value("device", nlohmann::json::object()));
  if (!mismatch.empty()) return {{"status", "no_exact_baseline"}, {"reason", mismatch}};
  const std::string backend = s.value("resolved", nlohmann::json::object()).value("backend", "");
  const std::string base_backend = base.value("resolved", nlohmann::json::object()).value("backend", "");
  if (backend != base_backend)
    return {{"status", "no_exact_baseline"},
            {"reason", fmt::format("the baseline ran the {} backend, this run {}", base_backend, backend)}};

  nlohmann::json out = compare_frames(base["hashes"], s["hashes"]);
  out.update(compare_buffers(base["hashes"], s["hashes"]));
  out["final_image_hash"] = {{"baseline", base.value("final_image_hash", "")},
                             {"current", s.value("final_image_hash", "")}};
  const bool same_image = out["final_image_hash"]["baseline"] == out["final_image_hash"]["current"];
  const bool same = same_image && out["first_differing_frame"].is_null() && !out.contains("frame_count") &&
                    out["differing_buffers"].empty() && out["added_buffers"].empty() && out["removed_buffers"].empty();
  out["status"] = same ? "unchanged" : "changed";
  if (same) return out;

  // How much, and where: the two final images side by side with a heat map.
  out["image"] = nullptr;
  const std::filesystem::path current_exr = in.run_dir / s.value("final_image", kFinalImageFile);
  if (!std::filesystem::exists(in.baseline_image)) {
    out["image_note"] = base.contains("image_dropped") ? "the baseline image was dropped: " +
                                                             base["image_dropped"].get<std::string>()
                                                       : "the baseline has no image";
    return out;
  }
  try {
    const Image b = read_exr(in.baseline_image).at(""), c = read_exr(current_exr).at("");
    if (b.width != c.width || b.height != c.height) {
      out["image_note"] = fmt::format("the image is {}x{}, the baseline's {}x{}", c.width, c.height, b.width, b.height);
      return out;
    }
    const ImageDifference d = image_difference(b, c);
    out["image"] = {{"relmse", json_figure(d.relmse)},
                    {"energy_ratio", json_figure(d.energy_ratio)},
                    {"max_abs_difference", json_figure(d.max_abs)},
                    {"pixels_differing", d.pixels_differing},
                    {"pixels", c.size()},
                    {"heat_scale", json_figure(d.heat_scale)},
                    {"precision", "both sides as stored: half floats (11 significant bits)"}};
    if (d.pixels_differing == 0)
      out["image_note"] = "the final images agree at half precision: the change is below 2^-11 relative, or "
                          "only in other frames or buffers";
    write_png_preview(in.evidence_dir / "baseline.png", b);
    write_png_preview(in.evidence_dir / "current.png", c);
    write_difference_png(in.evidence_dir / "difference.png", b, c, d.heat_scale);
    out["images"] = {{"baseline", (in.evidence_rel / "baseline.png").string()},
                     {"current", (in.evidence_rel / "current.png").string()},
                     {"difference", (in.evidence_rel / "difference.png").string()}};
  } catch (const std::exception& e) {
    out["image_note"] = std::string("cannot compare the images: ") + e.what();
  }
  return out;
}

}  // namespace gi
