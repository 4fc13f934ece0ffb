// The furnace check: the white furnace of the scenario's material
// model (the profile's brdf.model). Spheres of base colour 1 under uniform
// white light reflect, at each view angle, the BRDF's directional albedo; a
// model that conserves energy shows them as the background, 1 everywhere.
// Bevy judged four BRDF fixes by this image: #23442 (a full Lambert lobe
// under the specular one: gain), #23737 (Karis's polynomial F_ab: gain and
// loss on metals), #24243 (0.19's Fresnel layering: dielectrics lose up to
// three quarters at grazing angles) and #24246 (F0 blended before the lobe:
// partly metallic spheres lose a third).
//
// The check integrates the very code both renderers shade with
// (core/shared/brdf.h, core/white_furnace.h) over a grid of perceptual
// roughness × metallic × n·v, by quadrature rather than a noisy render, and
// fails where an albedo leaves [1 − max_loss, 1 + max_gain]. It needs no
// frame: alone in a scenario, it runs without a device.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/json_reader.h"
#include "core/png_preview.h"
#include "core/profile.h"
#include "core/white_furnace.h"
#include "checks/check_registry.h"
#include "core/run_options.h"
#include "gpu/realtime_settings.h"

namespace gi {
namespace {

std::vector<float> numbers(const JsonReader& r, const nlohmann::json& j, const std::string& path, double lo,
                           double hi) {
  std::vector<float> v;
  const nlohmann::json& a = r.array(j, path, 1);
  for (std::size_t i = 0; i < a.size(); ++i) v.push_back(r.number(a[i], JsonReader::at(path, i), lo, hi));
  return v;
}

nlohmann::json where(const FurnaceSample& s) {
  return {{"albedo", s.albedo},
          {"perceptual_roughness", s.perceptual_roughness},
          {"metallic", s.metallic},
          {"n_dot_v", s.nov}};
}

class FurnaceCheck final : public Check {
 public:
  explicit FurnaceCheck(const CheckContext& c)
      : scenario_(c.scenario), initial_(c.initial), options_(c.options), frames_(c.frames),
        model_name_(c.resolved_settings().brdf_model_name), model_(c.resolved_settings().brdf_model) {
    const JsonReader r(c.scenario.file.string());
    const nlohmann::json& p = c.spec.params;
    const std::string& at = c.spec.json_path;
    if (p.contains("perceptual_roughness"))
      roughness_ = numbers(r, p["perceptual_roughness"], at + "/perceptual_roughness", 0.0, 1.0);
    if (p.contains("metallic")) metallic_ = numbers(r, p["metallic"], at + "/metallic", 0.0, 1.0);
    if (p.contains("reflectance")) reflectance_ = r.number(p["reflectance"], at + "/reflectance", 0.0, 1.0);
    if (p.contains("view_angles")) view_angles_ = r.uint(p["view_angles"], at + "/view_angles", 2, 256);
    // Limits as written (r.number checks them and returns a float).
    if (p.contains("max_gain")) max_gain_ = (r.number(p["max_gain"], at + "/max_gain", 0.0, 1e6), p["max_gain"].get<double>());
    if (p.contains("max_loss")) max_loss_ = (r.number(p["max_loss"], at + "/max_loss", 0.0, 1.0), p["max_loss"].get<double>());
    alone_ = c.scenario.checks.size() == 1;
  }

  // Nothing of any frame: the model is fixed for the run.
  CheckNeeds needs() const override { return {.reads = {}, .frames = std::set<std::uint32_t>{}}; }
  void observe(const FrameView&, nlohmann::json&) override {}
  std::optional<std::string> decides_alone() const override {
    return alone_ ? std::optional<std::string>("device_free") : std::nullopt;
  }
  CheckResult result() override;

 private:
  void write_image(const std::vector<FurnaceSample>& samples, const std::vector<float>& nov) const;

  const Scenario& scenario_;
  const Scene& initial_;
  const RunOptions& options_;
  std::uint32_t frames_;
  std::string model_name_;
  std::uint32_t model_;
  bool alone_ = false;
  // Bevy's white-furnace scenes sweep roughness and metallic; 0.0316 is the
  // smallest perceptual roughness the clamp lets through.
  std::vector<float> roughness_{0.0316f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f, 1.0f};
  std::vector<float> metallic_{0.0f, 0.25f, 0.5f, 0.75f, 1.0f};
  float reflectance_ = 0.5f;  // StandardMaterial's default (F0 0.04)
  std::uint32_t view_angles_ = 20;
  // Main's model (#24246) loses 3 % on a rough white metal head on:
  // Filament's multiscatter factor is itself an approximation.
  double max_gain_ = 0.01, max_loss_ = 0.035;
};

CheckResult FurnaceCheck::result() {
  // n·v from 0.05 to 1: on a sphere's image n·v < 0.05 is the outer
  // 0.25 % of its disc (the area fraction is (n·v)²), where every model
  // darkens as the grazing lobes leave the hemisphere.
  std::vector<float> nov;
  for (std::uint32_t i = 0; i < view_angles_; ++i) nov.push_back(0.05f + 0.95f * float(i) / float(view_angles_ - 1));
  const std::vector<FurnaceSample> samples = white_furnace(model_, roughness_, metallic_, nov, reflectance_);
  const auto by_albedo = [](const FurnaceSample& a, const FurnaceSample& b) { return a.albedo < b.albedo; };
  const FurnaceSample lo = *std::min_element(samples.begin(), samples.end(), by_albedo);
  const FurnaceSample hi = *std::max_element(samples.begin(), samples.end(), by_albedo);
  const double floor = 1.0 - max_loss_, ceiling = 1.0 + max_gain_;
  std::size_t outside = 0;
  nlohmann::json rows = nlohmann::json::array();
  for (float m : metallic_) {
    double row_lo = 1e30, row_hi = -1e30;
    for (const FurnaceSample& s : samples)
      if (s.metallic == m) {
        row_lo = std::min(row_lo, s.albedo);
        row_hi = std::max(row_hi, s.albedo);
      }
    rows.push_back({{"metallic", m}, {"min_albedo", row_lo}, {"max_albedo", row_hi}});
  }
  for (const FurnaceSample& s : samples) outside += s.albedo < floor || s.albedo > ceiling;

  CheckResult c;
  c.name = "furnace";
  c.figures = {{"brdf_model", model_name_}, {"min", where(lo)},          {"max", where(hi)},
               {"by_metallic", rows},       {"points", samples.size()}, {"points_outside", outside}};
  c.limits = {{"max_gain", max_gain_}, {"max_loss", max_loss_}};
  write_image(samples, nov);
  c.evidence.push_back("furnace.png");
  const bool gains = hi.albedo > ceiling, loses = lo.albedo < floor;
  c.verdict = gains || loses ? Verdict::fail : Verdict::pass;
  const auto point = [](const FurnaceSample& s) {
    return fmt::format("{:.3f} at roughness {:.2f}, metallic {:.2f}, n·v {:.2f}", s.albedo, s.perceptual_roughness,
                       s.metallic, s.nov);
  };
  if (gains && (!loses || hi.albedo - 1.0 > 1.0 - lo.albedo))
    c.message = fmt::format("{}: a white sphere reflects more than it receives, {} (limit {:.3f}); {} of {} points "
                            "outside [{:.3f}, {:.3f}]",
                            model_name_, point(hi), ceiling, outside, samples.size(), floor, ceiling);
  else if (loses)
    c.message = fmt::format("{}: a white sphere loses energy, {} (limit {:.3f}); {} of {} points outside "
                            "[{:.3f}, {:.3f}]",
                            model_name_, point(lo), floor, outside, samples.size(), floor, ceiling);
  else
    c.message = fmt::format("{}: white furnace from {:.4f} to {:.4f} over {} points (limits [{:.3f}, {:.3f}])",
                            model_name_, lo.albedo, hi.albedo, samples.size(), floor, ceiling);
  return c;
}

// The furnace as Bevy shows it: one sphere per (metallic row, roughness
// column) on the background's radiance 1, drawn at exposure 0.5 so a gain
// is brighter than the background and a loss darker. Each pixel takes the
// albedo at its n·v, linear between the computed view angles.
void FurnaceCheck::write_image(const std::vector<FurnaceSample>& samples, const std::vector<float>& nov) const {
  const std::uint32_t cell = 48, cols = std::uint32_t(roughness_.size()), rows = std::uint32_t(metallic_.size());
  Image image(cols * cell, rows * cell);
  for (auto& px : image.pixels) px = glm::vec3(1.0f);
  const std::size_t per_point = nov.size();
  for (std::uint32_t row = 0; row < rows; ++row)
    for (std::uint32_t col = 0; col < cols; ++col) {
      // white_furnace nests roughness, then metallic, then n·v.
      const FurnaceSample* curve = &samples[(std::size_t(col) * rows + row) * per_point];
      for (std::uint32_t y = 0; y < cell; ++y)
        for (std::uint32_t x = 0; x < cell; ++x) {
          const float dx = (x + 0.5f) / cell * 2.0f - 1.0f, dy = (y + 0.5f) / cell * 2.0f - 1.0f;
          const float r2 = (dx * dx + dy * dy) / 0.81f;  // radius 0.9 of the cell
          if (r2 >= 1.0f) continue;
          const float c = std::max(std::sqrt(1.0f - r2), nov.front());
          std::size_t i = 0;
          while (i + 2 < per_point && nov[i + 1] < c) ++i;
          const float t = std::clamp((c - nov[i]) / (nov[i + 1] - nov[i]), 0.0f, 1.0f);
          const float a = float(curve[i].albedo + (curve[i + 1].albedo - curve[i].albedo) * t);
          image.at(col * cell + x, row * cell + y) = glm::vec3(a);
        }
    }
  std::filesystem::create_directories(options_.out_dir);
  write_png_preview(options_.out_dir / "furnace.png", image, 0.5f);
}

constexpr const char* kSchema = R"json({
  "type": "object",
  "additionalProperties": false,
  "description": "White furnace of the profile's brdf.model (Bevy #23442, #23737, #24243, #24246): the directional albedo of white spheres over perceptual roughness x metallic x n.v, from the shaders' own BRDF code, must lie in [1 - max_loss, 1 + max_gain]. Alone in a scenario it runs without a device.",
  "properties": {
    "name": {
      "const": "furnace"
    },
    "perceptual_roughness": {
      "type": "array",
      "items": {"type": "number", "minimum": 0, "maximum": 1},
      "minItems": 1,
      "description": "Perceptual roughness of the columns (default 0.0316, 0.1, 0.2, ..., 1)."
    },
    "metallic": {
      "type": "array",
      "items": {"type": "number", "minimum": 0, "maximum": 1},
      "minItems": 1,
      "description": "Metallic of the rows (default 0, 0.25, 0.5, 0.75, 1)."
    },
    "reflectance": {
      "type": "number",
      "minimum": 0,
      "maximum": 1,
      "description": "The dielectric's reflectance (default 0.5: F0 0.04)."
    },
    "view_angles": {
      "type": "integer",
      "minimum": 2,
      "maximum": 256,
      "description": "n.v values from 0.05 to 1 (default 20)."
    },
    "max_gain": {
      "type": "number",
      "minimum": 0,
      "description": "Largest allowed albedo above 1 (default 0.01)."
    },
    "max_loss": {
      "type": "number",
      "minimum": 0,
      "maximum": 1,
      "description": "Largest allowed albedo below 1 (default 0.035: main's model loses 3 % on a rough white metal)."
    }
  }
})json";

// What the verdict's figure estimates, the noise its limit allows for and
// how often that limit fails a pipeline without the bug (CheckModel).
const CheckModel kModel{
    "the directional albedo of the profile's BRDF over perceptual roughness x metallic x n.v, by "
    "quadrature of the shaders' own BRDF code",
    "none: a deterministic quadrature that draws no random number",
    CheckModel::Basis::exact,
    0.0,
    "0: the figure is the same at every seed"};

const RegisteredCheck<FurnaceCheck> kRegistration{{"furnace", kSchema, kModel, {}}};

}  // namespace
}  // namespace gi
