#include "replay/test_faults.h"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <string>
#include <thread>

#include "core/errors.h"
#include "gpu/device.h"

namespace gi {

void inject_test_fault(const std::string& scenario, std::uint32_t frame) {
  const char* env = std::getenv("GIHARNESS_TEST_FAULT");
  if (!env || !*env) return;
  const std::string spec = env;
  const auto bad = [&] {
    return InputError("GIHARNESS_TEST_FAULT", "",
                      "expected crash@N, hang@N or device_lost@N, optionally :<scenario>, got \"" + spec + "\"");
  };
  const std::size_t at = spec.find('@'), colon = spec.find(':');
  if (at == std::string::npos) throw bad();
  const std::string kind = spec.substr(0, at);
  const std::string frame_text = spec.substr(at + 1, colon == std::string::npos ? std::string::npos : colon - at - 1);
  std::uint32_t when = 0;
  try {
    std::size_t used = 0;
    when = static_cast<std::uint32_t>(std::stoul(frame_text, &used));
    if (used != frame_text.size()) throw bad();
  } catch (const std::exception&) {
    throw bad();
  }
  if (kind != "crash" && kind != "hang" && kind != "device_lost") throw bad();
  if (colon != std::string::npos && spec.substr(colon + 1) != scenario) return;
  if (frame != when) return;
  if (kind == "crash") std::raise(SIGSEGV);
  if (kind == "device_lost") gpu::Device::fault("device lost (forced by GIHARNESS_TEST_FAULT=" + spec + ")");
  for (;;) std::this_thread::sleep_for(std::chrono::hours(1));  // hang
}

}  // namespace gi
