#include "gpu/passes/frame_output.h"

#include <fmt/format.h>

#include "core/errors.h"
#include "gpu/device.h"
#include "gpu/shader_compiler.h"
#include "gpu/shaders/frame_output_bindings.h"
#include "gpu/timer.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

static_assert(sizeof(FrameOutputResults) == 64, "FrameOutputResults must match its std430 layout");
static_assert(sizeof(FrameOutputPush) == 16);
static_assert(FRAME_OUTPUT_GROUP * FRAME_OUTPUT_PIXELS_PER_INVOCATION == FRAME_OUTPUT_GROUP_PIXELS);

constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
constexpr std::size_t kNoiseDoubles = 6;  // per pixel and signal: rgb sum, rgb sum of squares

ComputePass make_pass(Device& device, ShaderCompiler& compiler, bool reduce) {
  std::vector<DescriptorBinding> bindings = {{BINDING_FRAME_PARTIALS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                             {BINDING_FRAME_RESULTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER}};
  if (!reduce)
    for (std::uint32_t b : {BINDING_FRAME_SIGNAL_0, BINDING_FRAME_SIGNAL_1, BINDING_FRAME_SIGNAL_2,
                            BINDING_FRAME_IMAGE, BINDING_FRAME_NOISE_SUMS})
      bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER});
  std::vector<ShaderDefine> defines;
  if (reduce) defines.push_back({"FRAME_OUTPUT_REDUCE", ""});
  return ComputePass(device, reduce ? "frame_output_reduce" : "frame_output",
                     compiler.compile_file(FrameOutput::kShader, defines).spirv, std::move(bindings),
                     sizeof(FrameOutputPush));
}

std::uint32_t checked_groups(std::uint32_t width, std::uint32_t height) {
  const std::uint64_t pixels = std::uint64_t(width) * height;
  const std::uint64_t groups = (pixels + FRAME_OUTPUT_GROUP_PIXELS - 1) / FRAME_OUTPUT_GROUP_PIXELS;
  if (groups > 65535) throw DeviceError(fmt::format("FrameOutput: {}x{} is over 65535 workgroups", width, height));
  return static_cast<std::uint32_t>(groups);
}

}  // namespace

FrameOutput::FrameOutput(Device& device, ShaderCompiler& compiler, std::uint32_t width, std::uint32_t height,
                         Mode mode)
    : width_(width), height_(height), mode_(mode), pass_(make_pass(device, compiler, false)),
      reduce_(make_pass(device, compiler, true)), hash_(device, compiler, 1),
      image_(device, std::size_t(pixels()) * 3 * sizeof(float), kStorage, "frame output image"),
      partials_(device, std::size_t(checked_groups(width, height)) * FRAME_SIGNALS * sizeof(double), kStorage,
                "frame output partials"),
      results_(device, sizeof(FrameOutputResults), kStorage, "frame output results"),
      // The reference mode keeps no noise window: a token buffer to bind.
      noise_(device, mode == Mode::reference ? 16 : std::size_t(pixels()) * signals() * kNoiseDoubles * sizeof(double),
             kStorage, "temporal noise sums"),
      results_host_(device, results_) {
  for (ComputePass* p : {&pass_, &reduce_}) {
    p->bind_buffer(BINDING_FRAME_PARTIALS, partials_);
    p->bind_buffer(BINDING_FRAME_RESULTS, results_);
  }
  pass_.bind_buffer(BINDING_FRAME_IMAGE, image_);
  pass_.bind_buffer(BINDING_FRAME_NOISE_SUMS, noise_);
}

std::uint32_t FrameOutput::signals() const { return mode_ == Mode::di_gi ? FRAME_SIGNALS : 2u; }

void FrameOutput::bind(const Buffer& signal0, const Buffer* signal1, const Buffer* signal2) {
  const bool two = mode_ != Mode::di, three = mode_ == Mode::di_gi;
  if ((two && !signal1) || (three && !signal2)) throw DeviceError("FrameOutput::bind: a signal buffer is missing");
  pass_.bind_buffer(BINDING_FRAME_SIGNAL_0, signal0);
  // Unused signals are bound to the first so the set stays complete.
  pass_.bind_buffer(BINDING_FRAME_SIGNAL_1, two ? *signal1 : signal0);
  pass_.bind_buffer(BINDING_FRAME_SIGNAL_2, three ? *signal2 : signal0);
}

void FrameOutput::restart_noise() {
  if (mode_ == Mode::reference) throw DeviceError("FrameOutput: the reference mode keeps no temporal noise");
  noise_.fill_zero();
}

void FrameOutput::record(VkCommandBuffer cmd, GpuTimer& timer) {
  FrameOutputPush push{};
  push.pixels = pixels();
  push.mode = mode_ == Mode::di ? FRAME_OUTPUT_DI : mode_ == Mode::di_gi ? FRAME_OUTPUT_DI_GI : FRAME_OUTPUT_REFERENCE;
  push.accumulate_noise = accumulate_noise_ && mode_ != Mode::reference ? 1u : 0u;
  push.groups = checked_groups(width_, height_);
  timer.begin(cmd, "frame_output");
  results_.record_fill_zero(cmd);
  hash_.record_clear(cmd);
  pass_.dispatch(cmd, push.groups, 1, 1, &push);
  compute_barrier(cmd);
  reduce_.dispatch(cmd, 1, 1, 1, &push);
  hash_.record(cmd, {&image_, image_.size()}, 0);
  timer.end(cmd);
  compute_barrier(cmd);
  results_host_.record_copy(cmd);
  hash_.record_to_host(cmd);
}

FrameMeasures FrameOutput::measures() const {
  const FrameOutputResults r = results_host_.read<FrameOutputResults>(1)[0];
  auto mean = [&](std::uint32_t s) { return r.finite_pixels[s] ? r.luminance_sum[s] / double(r.finite_pixels[s]) : 0.0; };
  FrameMeasures m;
  m.output_luminance = mean(FRAME_SIGNAL_OUTPUT);
  m.di_luminance = mean(FRAME_SIGNAL_DI);
  m.gi_luminance = mean(FRAME_SIGNAL_GI);
  m.specular_luminance = mean(FRAME_SIGNAL_SPECULAR);
  m.nonfinite_components = r.nonfinite_components;
  m.image_hash = hash_.result(0);
  return m;
}

Image FrameOutput::image() const {
  Image img(width_, height_);
  image_.download_bytes(img.pixels.data(), img.pixels.size() * sizeof(glm::vec3));
  return img;
}

std::map<std::string, NoiseSums> FrameOutput::noise_sums() const {
  if (mode_ == Mode::reference) return {};
  const std::vector<double> all = noise_.download<double>(std::size_t(pixels()) * signals() * kNoiseDoubles);
  static const char* names[] = {"output", "di", "gi", "specular"};
  std::map<std::string, NoiseSums> out;
  for (std::uint32_t s = 0; s < signals(); ++s) {
    NoiseSums& n = out[names[s]];
    n.sum.resize(pixels());
    n.sum_sq.resize(pixels());
    for (std::size_t p = 0; p < pixels(); ++p) {
      const double* d = &all[(std::size_t(s) * pixels() + p) * kNoiseDoubles];
      n.sum[p] = glm::dvec3(d[0], d[1], d[2]);
      n.sum_sq[p] = glm::dvec3(d[3], d[4], d[5]);
    }
  }
  return out;
}

}  // namespace gi::gpu
