#include "core/cpu_schedule.h"

#include <filesystem>
#include <fstream>
#include <system_error>

namespace gi {

CpuSchedule cpu_schedule_now() {
  CpuSchedule s;
  std::error_code ec;
  std::filesystem::directory_iterator tasks("/proc/self/task", ec);
  if (ec) return s;
  for (const auto& task : tasks) {
    std::ifstream in(task.path() / "schedstat");
    std::uint64_t run = 0, wait = 0;
    if (!(in >> run >> wait)) continue;  // a thread that just ended
    s.available = true;
    s.run_ns += run;
    s.wait_ns += wait;
  }
  return s;
}

CpuSchedule cpu_schedule_between(const CpuSchedule& before, const CpuSchedule& after) {
  CpuSchedule d;
  d.available = before.available && after.available;
  if (!d.available) return d;
  d.run_ns = after.run_ns > before.run_ns ? after.run_ns - before.run_ns : 0;
  d.wait_ns = after.wait_ns > before.wait_ns ? after.wait_ns - before.wait_ns : 0;
  return d;
}

double cpu_wait_share(const CpuSchedule& d) {
  const double total = double(d.run_ns) + double(d.wait_ns);
  return total > 0 ? double(d.wait_ns) / total : 0.0;
}

}  // namespace gi
