#include "checks/realtime_reference_check.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/exr_io.h"
#include "core/reference/reference_cache.h"
#include "reports/json_figures.h"

namespace gi {
namespace {

double lum(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// One chain's frame against the reference: compare() treats (a, b) as halves
// of the mean (a+b)/2; a single chain has twice that noise variance.
Comparison single_chain(const Image& a, const Image& b, const ReferenceComparisons::Reference& ref) {
  Comparison c = compare(a, a, b, ref.mean, ref.half_a, ref.half_b);
  c.noise_x *= 2.0;
  c.combined_noise = c.noise_x + c.noise_y;
  c.relmse_over_noise = c.combined_noise > 0 ? c.relmse / c.combined_noise : 0.0;
  c.bias_relmse = std::max(0.0, c.relmse - c.combined_noise);
  c.energy_ratio_sigma *= std::sqrt(2.0);  // dominated by the GPU side at realtime sample counts
  return c;
}

}  // namespace

Image chain_average(const std::vector<Image>& chains) {
  Image m(chains.at(0).width, chains[0].height);
  for (std::size_t i = 0; i < m.size(); ++i)
    for (const Image& c : chains) m.pixels[i] += c.pixels[i] / float(chains.size());
  return m;
}

double edge_region_relmse(const Image& x, const Image& y) {
  const int w = static_cast<int>(y.width), h = static_cast<int>(y.height);
  double sum = 0;
  std::size_t n = 0;
  for (int py = 0; py < h; ++py)
    for (int px = 0; px < w; ++px) {
      double lo = INFINITY, hi = 0;
      for (int dy = -3; dy <= 3; ++dy)
        for (int dx = -3; dx <= 3; ++dx) {
          const int qx = std::clamp(px + dx, 0, w - 1), qy = std::clamp(py + dy, 0, h - 1);
          const double l = lum(y.pixels[std::size_t(qy) * w + qx]);
          lo = std::min(lo, l);
          hi = std::max(hi, l);
        }
      if (!(hi > 2.0 * lo + 1e-3)) continue;
      const std::size_t i = std::size_t(py) * w + px;
      for (int c = 0; c < 3; ++c) {
        const double d = double(x.pixels[i][c]) - double(y.pixels[i][c]);
        sum += d * d / (double(y.pixels[i][c]) * y.pixels[i][c] + kRelmseEpsilon);
      }
      n += 3;
    }
  return n ? sum / double(n) : 0.0;
}

void RealtimeReferenceCheck::compare_frame(std::uint32_t frame, const Scene& scene, const RealtimeEstimate& gpu) {
  const Reference ref = reference(scene, gpu.frames[0].width, gpu.frames[0].height, !gpu.full_gi);
  FrameComparison f;
  f.frame = frame;
  f.window_start = gpu.window_start;
  f.window_frames = gpu.window_frames;
  f.full_gi = gpu.full_gi;
  f.chains = std::uint32_t(gpu.means.size());
  const Comparison chains = compare_chains(gpu.means, ref.mean, ref.half_a, ref.half_b);
  const Image mean = chain_average(gpu.means);
  // Two chains: the energy σ summed over pixels (many degrees of freedom, no
  // image-wide error); more: the chains' own spread.
  f.temporal = f.chains >= 3 ? chains : compare(mean, gpu.means[0], gpu.means[1], ref.mean, ref.half_a, ref.half_b);
  f.energy_ratio_sigma_chains = chains.energy_ratio_sigma;
  f.per_frame = single_chain(gpu.frames[0], gpu.frames[1], ref);
  f.verdict = f.temporal.judge(params_.relmse_noise_factor, params_.energy_tolerance, params_.relmse_tolerance);
  f.temporal_edge_relmse = edge_region_relmse(mean, ref.mean);
  f.reference_seconds = ref.seconds;
  f.reference_cached = ref.cached;
  f.evidence = fmt::format("reference/frame_{:05}.exr", frame);
  write_exr(out_dir_ / f.evidence,
            {{"gpu_temporal_mean", &mean}, {"gpu_frame", &gpu.frames[0]}, {gpu.full_gi ? "embree_full_gi" : "embree_di", &ref.mean}});
  frames_.push_back(std::move(f));
}

CheckResult RealtimeReferenceCheck::result() const {
  CheckResult r = start_result();
  r.limits["warmup_frames"] = params_.warmup_frames;
  r.limits["judged_on"] = fmt::format("temporal mean over the static window of {} independent chains", params_.chains);
  r.limits["chains"] = params_.chains;
  if (frames_.empty()) return r;
  Tally tally;
  nlohmann::json list = nlohmann::json::array();
  for (const FrameComparison& f : frames_) {
    list.push_back({{"frame", f.frame},
                    {"window_start", f.window_start},
                    {"window_frames", f.window_frames},
                    {"temporal_mean", comparison_json(f.temporal)},
                    {"temporal_mean_edge_region_relmse", json_figure(f.temporal_edge_relmse)},
                    {"chains", f.chains},
                    {"energy_ratio_sigma_chains", json_figure(f.energy_ratio_sigma_chains)},
                    {"energy_dof", f.temporal.energy_dof},
                    {"per_frame", comparison_json(f.per_frame)},
                    {"reference_seconds", json_figure(f.reference_seconds)},
                    {"reference_cached", f.reference_cached},
                    {"verdict", verdict_name(f.verdict)},
                    {"reason", f.verdict.reason}});
    r.evidence.push_back(f.evidence);
    tally.add(f.frame, f.verdict,
              fmt::format("frame {} (temporal mean of {} frames): {}; measured energy ratio {:.4f} "
                                  "(1 sigma {:.2g}), relMSE {:.3g} = {:.2f}x combined noise",
                                  f.frame, f.window_frames, f.verdict.reason, f.temporal.energy_ratio,
                                  f.temporal.energy_ratio_sigma, f.temporal.relmse, f.temporal.relmse_over_noise),
              r);
  }
  r.figures["frames"] = list;
  const FrameComparison& last = frames_.back();
  r.verdict = tally.verdict();
  r.message = r.verdict == Verdict::pass
                  ? fmt::format("frame {}: {} temporal mean of {} frames: relMSE {:.3g} = {:.2f}x combined noise "
                                "{:.3g}; energy ratio {:.4f}; per frame relMSE {:.3g}",
                                last.frame, last.full_gi ? "full-image" : "DI", last.window_frames, last.temporal.relmse, last.temporal.relmse_over_noise,
                                last.temporal.combined_noise, last.temporal.energy_ratio, last.per_frame.relmse)
                  : tally.first_problem;
  return r;
}

}  // namespace gi
