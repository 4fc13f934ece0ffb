// TEMPORARY while gpu/renderer.h is written.
#include "replay/run_scenario.h"
#include "core/errors.h"
namespace gi {
std::filesystem::path cache_root() { return "/tmp/giharness-cache"; }
RunResult run_scenario(const Scenario&, const RunOptions&) { throw DeviceError("renderer not built yet"); }
}
