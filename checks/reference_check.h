// The `reference` check (docs/design.md §6): the GPU image at chosen frames against
// the Embree reference of the same scene state, with both estimators' noise.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/metrics.h"
#include "core/scenario.h"
#include "core/scene.h"
#include "checks/check_result.h"

namespace gi {

// The most independent chains a check may ask for (each one a whole pipeline).
inline constexpr std::uint32_t kMaxChains = 16;

struct ReferenceCheckParams {
  std::vector<std::uint32_t> frames;  // default: the last frame
  std::uint32_t spp = 1024;           // Embree samples per pixel
  double relmse_noise_factor = 3.0;   // relMSE ≤ factor × combined noise
  double energy_tolerance = 0.01;     // |energy ratio − 1| ≤ tolerance
  double relmse_tolerance = 0.0;      // allowed bias in relMSE (0: none)
  // Realtime mode only: frames after the start of each static window that the
  // temporal mean leaves out, so the comparison judges the pipeline's steady
  // state (a world cache converging over ~100 frames), not its warm-up; the
  // warm-up itself is the blend_lag check's business. 0: the whole window.
  std::uint32_t warmup_frames = 0;
  // Realtime mode only: independent chains (pipelines that share no state).
  // With 2 the energy σ sums the pixels' noise as if independent; with 3 or
  // more it comes from the chains' spread (K − 1 degrees of freedom), which
  // also holds the error a chain shares over the whole image (the world
  // cache's cell placement, frozen for a run: README "Error bars").
  std::uint32_t chains = 2;
};

// Reads the check's parameters; InputError at <check json_path>/<key>.
ReferenceCheckParams reference_check_params(const CheckSpec& spec, const Scenario& scenario,
                                            std::uint32_t frame_count);

// What the CLI's own reference renders (`giharness reference`, `sweep`)
// take from a scenario's reference check, so its parameters are read here
// only: the samples per pixel it asks for (`fallback` without the check)...
std::uint32_t scenario_reference_spp(const Scenario& scenario, std::uint32_t fallback);
// ...and the scenario's checks without it, for a tool that measures error
// against its own converged reference instead.
nlohmann::json without_reference_checks(const nlohmann::json& checks);

// The GPU side of one compared frame.
struct GpuEstimate {
  Image mean, half_a, half_b;
  std::uint64_t samples = 0;  // per pixel, in the accumulation window
};

// What the reference check of both modes shares: the parameters, the
// Embree reference of a compared frame's scene (rendered, or loaded from
// the cache), and the verdict folded over the compared frames.
class ReferenceComparisons {
 public:
  ReferenceComparisons(ReferenceCheckParams params, std::uint32_t seed, std::filesystem::path cache_dir,
                       std::filesystem::path out_dir);
  const ReferenceCheckParams& params() const { return params_; }
  bool wants(std::uint32_t frame) const;
  struct Reference {
    Image mean, half_a, half_b;
    double seconds = 0.0;
    bool cached = false;
  };

 protected:
  // Embree's image of `scene` at the check's spp and seed (direct lighting
  // only, or the full path tracer).
  Reference reference(const Scene& scene, std::uint32_t width, std::uint32_t height, bool direct_only) const;
  // The verdict over the compared frames, in order.
  struct Tally {
    bool any_fail = false, any_inconclusive = false;
    std::string first_problem;
    // One compared frame; `problem` describes it when it did not pass.
    void add(std::uint32_t frame, const ComparisonVerdict& verdict, const std::string& problem, CheckResult& r);
    Verdict verdict() const;
  };
  // name "reference", the limits, and the inconclusive verdict when no frame was compared.
  CheckResult start_result() const;

  ReferenceCheckParams params_;
  std::uint32_t seed_;
  std::filesystem::path cache_dir_, out_dir_;
};

// A frame's verdict as the summary spells it.
const char* verdict_name(const ComparisonVerdict& v);
// A comparison's figures as the summary spells them.
nlohmann::json comparison_json(const Comparison& c);

class ReferenceCheck : public ReferenceComparisons {
 public:
  using ReferenceComparisons::ReferenceComparisons;
  // Renders (or loads) the Embree image of `scene` and compares; writes
  // reference/frame_NNNNN.exr (gpu, embree, error layers) as evidence.
  void compare_frame(std::uint32_t frame, const Scene& scene, const GpuEstimate& gpu);
  CheckResult result() const;

 private:
  struct FrameComparison {
    std::uint32_t frame;
    Comparison comparison;
    ComparisonVerdict verdict;
    std::uint64_t gpu_samples;
    std::uint32_t reference_spp;
    double reference_seconds;
    bool reference_cached;
    std::string evidence;
  };
  std::vector<FrameComparison> frames_;
};

}  // namespace gi
