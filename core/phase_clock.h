// Where a run's wall time goes: named phases (compiling shaders, creating
// pipelines, rendering references, rendering frames), timed where they
// happen and summed per process. A phase inside another counts once, in the
// inner one (a reference rendered by a check during the frame loop is
// "reference" time, not "frames" time), so the phases add up to at most the
// wall time. summary.json's "wall_breakdown" (replay/run_summary.cpp) and the
// nightly's total report them; nothing here changes what a run computes.
#pragma once
#include <chrono>
#include <map>
#include <string>

namespace gi {

// The phases, as they appear in reports.
namespace phase {
inline constexpr const char* kShaderSources = "shader_sources";  // glslang and the SPIR-V cache
inline constexpr const char* kPipelines = "pipelines";           // the driver's vkCreateComputePipelines
inline constexpr const char* kReferences = "references";         // Embree references: rendered or read from the cache
inline constexpr const char* kFrames = "frames";                 // the frame loop, GPU work included
inline constexpr const char* kScene = "scene";                   // the scenario's scene: import, textures, flattening
inline constexpr const char* kGpuSetup = "gpu_setup";            // the pipelines' buffers, the BVH, uploads
inline constexpr const char* kSummary = "summary";               // summary.json and what it computes
inline constexpr const char* kEqualTime = "equal_time";          // the equal-time peers (--equal-time, the nightly's)
inline constexpr const char* kShaderPrewarm = "shader_prewarm";  // waiting for the driver's compile ahead (gpu/shader_prewarm.h)
}  // namespace phase

// Seconds per phase, exclusive of nested phases, since the process started.
std::map<std::string, double> phase_seconds();

// Times one phase from construction to destruction (same thread).
class PhaseScope {
 public:
  explicit PhaseScope(const char* phase);
  ~PhaseScope();
  PhaseScope(const PhaseScope&) = delete;
  PhaseScope& operator=(const PhaseScope&) = delete;

 private:
  const char* phase_;
  std::chrono::steady_clock::time_point start_;
  double nested_seconds_ = 0;  // spent in phases opened inside this one
  PhaseScope* outer_;
};

}  // namespace gi
