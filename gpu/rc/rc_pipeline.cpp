#include "gpu/rc/rc_pipeline.h"

#include "gpu/device.h"
#include "gpu/timer.h"

namespace gi::gpu {

using namespace gi::shader;

namespace {

constexpr VkBufferUsageFlags kUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

RcBuffers make_buffers(Device& device, const RcSettings& s) {
  const VkDeviceSize pixels = VkDeviceSize(s.width) * s.height;
  RcBuffers b;
  b.shapes = Buffer(device, sizeof(RcShape) * RC_MAX_SHAPES, kUsage, "rc_shapes");
  b.scene = Buffer(device, pixels * 16, kUsage, "rc_scene");
  b.distance = Buffer(device, pixels * 4, kUsage, "rc_distance");
  // JFA's seeds only where it runs (a scenario records only what it uses).
  for (int i = 0; i < 2; ++i) {
    b.seeds[i] = Buffer(device, s.jfa ? pixels * 4 : 0, kUsage, "rc_seeds_" + std::to_string(i));
    b.cascades[i] = Buffer(device, pixels * 16, kUsage, "rc_cascade_" + std::to_string(i));
  }
  b.mipmap = Buffer(device, VkDeviceSize(s.mip_width()) * s.mip_height() * 16, kUsage, "rc_mipmap");
  b.output = Buffer(device, pixels * 16, kUsage, "rc_output");
  return b;
}

}  // namespace

Image rc_image(const Buffer& buffer, std::uint32_t width, std::uint32_t height) {
  const std::vector<glm::vec4> texels = buffer.download<glm::vec4>(std::size_t(width) * height);
  Image img(width, height);
  for (std::size_t i = 0; i < texels.size(); ++i) img.pixels[i] = glm::vec3(texels[i]);
  return img;
}

RcPipeline::RcPipeline(Device& device, ShaderCompiler& compiler, const RcSettings& settings)
    : device_(device), settings_(settings), buffers_(make_buffers(device, settings)),
      scene_(device, compiler, buffers_), cascade_(device, compiler, buffers_), mipmap_(device, compiler, buffers_),
      apply_(device, compiler, buffers_) {
  if (settings_.jfa) {
    jfa_seed_.emplace(device, compiler, buffers_);
    jfa_step_.emplace(device, compiler, buffers_);
  } else {
    distance_.emplace(device, compiler, buffers_);
  }
}

void RcPipeline::set_canvas(const Canvas& canvas) {
  const std::vector<RcShape> shapes = canvas.gpu_shapes();
  buffers_.shapes.upload(shapes);
  shape_count_ = std::uint32_t(shapes.size());
}

RcPush RcPipeline::push_for(std::uint32_t cascade) const {
  RcPush p{};
  p.width = settings_.width;
  p.height = settings_.height;
  p.shape_count = shape_count_;
  const RcProbe probe = settings_.probe(cascade);
  p.probe_width = probe.width;
  p.probe_start = probe.start;
  p.probe_range = probe.range;
  p.max_steps = settings_.max_steps;
  p.hit_epsilon = settings_.hit_epsilon;
  p.mipmap_mode = settings_.mipmap_mode;
  p.merge_fix = settings_.merge;
  p.mip_width = settings_.mip_width();
  p.mip_height = settings_.mip_height();
  return p;
}

// The farthest cascade writes cascades[0] without merging; each nearer one
// writes the other buffer, merging the one before: cascade c lands in
// cascades[(n − 1 − c) mod 2].
std::uint32_t RcPipeline::cascade0_buffer() const { return (settings_.cascades - 1) % 2; }

void RcPipeline::record(VkCommandBuffer cmd, GpuTimer* timer,
                        const std::function<void(VkCommandBuffer, std::uint32_t, const Buffer&)>& after_cascade) const {
  auto timed = [&](const char* name, const std::function<void()>& f) {
    if (timer) timer->begin(cmd, name);
    f();
    if (timer) timer->end(cmd);
  };
  const RcPush base = push_for(0);
  timed("rc_scene", [&] { scene_.record(cmd, base); });
  if (settings_.jfa) {
    timed("jfa_seed", [&] { jfa_seed_->record(cmd, base); });
    timed("jfa_step", [&] { jfa_step_->record(cmd, base); });
  } else {
    timed("rc_distance", [&] { distance_->record(cmd, base); });
  }
  timed("rc_cascade", [&] {
    const std::uint32_t n = settings_.cascades;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t c = n - 1 - i;
      RcPush push = push_for(c);
      push.merge = i == 0 ? 0u : 1u;
      cascade_.record(cmd, i % 2, push);
      if (after_cascade) after_cascade(cmd, c, buffers_.cascades[i % 2]);
    }
  });
  timed("rc_mipmap", [&] { mipmap_.record(cmd, cascade0_buffer(), base); });
  timed("rc_apply", [&] { apply_.record(cmd, base); });
}

Image RcPipeline::output() const { return rc_image(buffers_.output, settings_.width, settings_.height); }
Image RcPipeline::scene() const { return rc_image(buffers_.scene, settings_.width, settings_.height); }
Image RcPipeline::cascade0() const {
  return rc_image(buffers_.cascades[cascade0_buffer()], settings_.width, settings_.height);
}
Image RcPipeline::mipmap() const { return rc_image(buffers_.mipmap, settings_.mip_width(), settings_.mip_height()); }
std::vector<float> RcPipeline::distance() const {
  return buffers_.distance.download<float>(std::size_t(settings_.width) * settings_.height);
}

}  // namespace gi::gpu
