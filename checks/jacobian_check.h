// The `jacobian` check (docs/design.md §6): ReSTIR GI's reuse weights stay bounded and
// finite. Per frame it reads the GI statistics (gpu/passes/gi_pipeline.h,
// integer atomics: 160 bytes, so a 100 000-frame soak keeps flat memory) and
// folds them into run totals; it fails at the first frame with an accepted
// J above the limit or a non-finite reservoir or output value, and names it.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/scenario.h"
#include "gpu/passes/gi_pipeline.h"
#include "checks/check_result.h"

namespace gi {

struct JacobianCheckParams {
  double max_jacobian = 1.2;  // default: the profile's restir_gi.jacobian_reject
};

// InputError at <check json_path>/max_jacobian.
JacobianCheckParams jacobian_check_params(const CheckSpec& spec, const Scenario& scenario, double profile_reject);

class JacobianCheck {
 public:
  explicit JacobianCheck(JacobianCheckParams params) : params_(params) {}
  // Returns this frame's figures for the frame record.
  nlohmann::json record_frame(std::uint32_t frame, const gpu::GiFrameStats& stats);
  CheckResult result() const;

 private:
  JacobianCheckParams params_;
  std::uint64_t frames_ = 0, merges_ = 0, rejections_ = 0;
  std::uint64_t nonfinite_jacobians_ = 0, nonfinite_reservoirs_ = 0, nonfinite_output_ = 0;
  double max_accepted_j_ = 0.0;
  std::uint32_t max_accepted_j_frame_ = 0;
  std::array<std::uint64_t, 32> histogram_{};
  std::optional<std::uint32_t> first_bad_frame_;
  std::string first_bad_reason_;
};

}  // namespace gi
