// The ray-list pass (gpu/shaders/ray_list_trace.comp): uploads a scene,
// builds the Device's tracing backend (TLAS or BVH), and traces ray lists
// through trace_closest / trace_unoccluded. Production code (once named
// ray_trace_test) that serves tests and benchmarks. The backend cross-check
// (tests/backend_crosscheck_test.cpp) and `giharness bench` use it; the
// frame pipeline does not.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "core/scene_flatten.h"
#include "gpu/acceleration_structures.h"
#include "gpu/buffer.h"
#include "gpu/scene_texture_buffers.h"
#include "gpu/bvh_buffers.h"
#include "gpu/compute_pass.h"
#include "gpu/passes/ray_list_trace_types.h"
#include "gpu/timer.h"

namespace gi::gpu {

class ShaderCompiler;

class RayListTrace {
 public:
  static constexpr const char* kShader = "gpu/shaders/ray_list_trace.comp";

  // Sets `compiler`'s backend defines from device.backend() and compiles.
  RayListTrace(Device& device, ShaderCompiler& compiler, const FlatGeometry& geometry,
               const FlatInstances& instances, const std::vector<bool>& visible);
  ~RayListTrace();
  RayListTrace(const RayListTrace&) = delete;
  RayListTrace& operator=(const RayListTrace&) = delete;

  // mode: shader::TRACE_MODE_* bits. Submits, waits, returns one result per ray.
  std::vector<shader::TestResult> trace(const std::vector<shader::TestRay>& rays, std::uint32_t mode);
  // GPU time of the last trace() dispatch (timestamps), ms.
  double last_ms() const { return last_ms_; }

 private:
  Device& device_;
  Buffer vertices_, indices_, instances_, materials_, lights_, frame_, dfg_lut_;
  SceneTextureBuffers textures_;
  std::optional<AccelerationStructures> as_;
  std::optional<BvhBuffers> bvh_;
  ComputePass pass_;
  GpuTimer timer_;
  Buffer rays_, results_;
  double last_ms_ = 0.0;
};

}  // namespace gi::gpu
