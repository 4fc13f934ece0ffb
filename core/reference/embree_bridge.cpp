#include "core/reference/embree_bridge.h"

#include <tbb/task_arena.h>

#include "core/errors.h"
#include "core/reference/embree_geometry.h"

namespace gi {
namespace {

void record_error(void* user, RTCError code, const char* str) {
  auto* message = static_cast<std::string*>(user);
  if (message->empty()) *message = "Embree error " + std::to_string(int(code)) + ": " + (str ? str : "");
}

}  // namespace

EmbreeScene::EmbreeScene(const FlatGeometry& g, const FlatInstances& f, const std::vector<std::uint8_t>& visible) {
  device_ = rtcNewDevice(nullptr);
  if (!device_) throw DeviceError("Embree: rtcNewDevice failed (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(device_, record_error, &error_);
  scene_ = rtcNewScene(device_);
  // Robust (watertight) traversal: no leaks through shared edges.
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  for (std::uint32_t i = 0; i < f.instances.size(); ++i) {
    if (i >= visible.size() || !visible[i] || f.instances[i].triangle_count == 0) continue;
    if (!attach_instance_geometry(device_, scene_, g, f.instances[i], i))  // geomID == instance index
      throw DeviceError("Embree: cannot allocate buffers: " + error_);
  }
  tbb::task_arena serial(1);
  serial.execute([&] { rtcCommitScene(scene_); });
  if (!error_.empty()) throw DeviceError(error_);
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

}  // namespace gi
