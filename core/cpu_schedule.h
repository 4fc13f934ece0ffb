// How much CPU this process's threads got, and how long they waited for it,
// from the kernel's per-thread scheduler statistics (/proc/self/task/*/schedstat:
// ns on a CPU, ns runnable but waiting on a run queue, timeslices).
//
// Why: on lavapipe a pass's "GPU" time is CPU time of the driver's threads.
// When another job loads the machine (a build beside the nightly) those
// threads wait, and every pass reads slower though nothing changed. The
// wait is measured, so the timing verdict (reports/timing_verdict.h) can
// say how loaded a frame was and judge only the frames that were not.
#pragma once
#include <cstdint>

namespace gi {

struct CpuSchedule {
  bool available = false;      // false where the kernel has no schedstat (then both are 0)
  std::uint64_t run_ns = 0;    // summed over the process's threads
  std::uint64_t wait_ns = 0;   // runnable, not running: waiting for a CPU
};

// The process's counters now (a few dozen microseconds: one small file per thread).
CpuSchedule cpu_schedule_now();

// What happened between two readings; threads that ended in between take
// their counts with them, so a difference is clamped at 0.
CpuSchedule cpu_schedule_between(const CpuSchedule& before, const CpuSchedule& after);

// The share of the CPU time this process wanted that it waited for:
// wait / (run + wait), 0 when nothing ran.
double cpu_wait_share(const CpuSchedule& interval);

}  // namespace gi
