// Per-frame noise of the realtime signals (DI, GI, specular, output), two
// ways, for summary.json's "noise":
//
// - chain: from two independent chains A and B of the last frame,
//   mean((A − B)² / 2 / (m² + 0.01)). Cheap, but A and B share the world
//   cache, so the part of the noise that comes from the cache's own
//   frame-to-frame fluctuation is common to both and cancels: it measures
//   the reservoirs' sampling noise, not all that the image shows.
// - temporal: the per-pixel variance of chain A over the frames of a static
//   window (the second half of the run, restarted by any scene change),
//   mean(var_t(A) / (m² + 0.01)). This is the flicker a viewer sees,
//   the cache's fluctuation included. Frames are correlated by reuse, which
//   biases the sample variance low by about the correlation time over the
//   window length; with 80 frames and reuse histories of ≤ 20 frames the
//   figure is within ~25 % of the marginal variance.
//
// m is the temporal mean of the whole output at that pixel, so the signals'
// figures are on one scale and add up to about the output's.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gpu/passes/frame_output.h"

namespace gi {

// The window's bookkeeping; the per-pixel sums of chain A's signals are
// kept on the GPU (gpu/passes/frame_output.h) and read back once, at the end.
class TemporalNoise {
 public:
  // Starts (or restarts) the window at `frame` (the caller zeroes the sums).
  void restart(std::uint32_t frame);
  // One more frame added to the sums.
  void count_frame() { ++count_; }
  std::uint32_t frames() const { return count_; }
  std::uint32_t first_frame() const { return first_; }
  // {signal: figure} from the window's sums; "output" must be among them.
  // Empty with fewer than 8 frames.
  nlohmann::json figures(const std::map<std::string, gpu::NoiseSums>& sums) const;

 private:
  std::uint32_t count_ = 0;
  std::uint32_t first_ = 0;
};

}  // namespace gi
