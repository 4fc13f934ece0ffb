// Faults on demand, for the tests of what survives them (the nightly's
// process per scenario): GIHARNESS_TEST_FAULT=<kind>@<frame>[:<scenario>]
// makes a run (of that scenario only, when named) misbehave when it reaches
// that frame:
//   crash@N        raise SIGSEGV
//   hang@N         sleep and never return
//   device_lost@N  end as a lost device does (gpu::Device::fault: exit 3)
// Unset or empty: nothing. A malformed value is bad input (exit 2) at the
// first frame, so a typo cannot pass as a clean run.
#pragma once
#include <cstdint>
#include <string>

namespace gi {

void inject_test_fault(const std::string& scenario, std::uint32_t frame);

}  // namespace gi
