#include "gpu/passes/timing_calibration.h"

#include "gpu/shader_compiler.h"
#include "gpu/shaders/timing_calibration_bindings.h"
#include "gpu/timer.h"

namespace gi::gpu {

namespace {

ComputePass make_pass(Device& device, ShaderCompiler& compiler) {
  return ComputePass(device, TimingCalibration::kTimerName, compiler.compile_file(TimingCalibration::kShader).spirv,
                     {{BINDING_CALIBRATION_TABLE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}}, sizeof(std::uint32_t));
}

}  // namespace

TimingCalibration::TimingCalibration(Device& device, ShaderCompiler& compiler)
    : table_(device, CALIBRATION_TABLE_WORDS * sizeof(std::uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
             "timing calibration table"),
      pass_(make_pass(device, compiler)) {
  table_.fill_zero();
  pass_.bind_buffer(BINDING_CALIBRATION_TABLE, table_);
}

void TimingCalibration::record(VkCommandBuffer cmd, GpuTimer& timer) const {
  const std::uint32_t iterations = kIterations;
  timer.begin(cmd, kTimerName);
  pass_.dispatch(cmd, group_count(kInvocations, CALIBRATION_GROUP), 1, 1, &iterations);
  timer.end(cmd);
  compute_barrier(cmd);
}

}  // namespace gi::gpu
