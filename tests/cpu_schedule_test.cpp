// The process's CPU run and wait counters (core/cpu_schedule.h), which the
// timing verdict uses to tell a loaded machine from a slow pass.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "core/cpu_schedule.h"

namespace gi {
namespace {

TEST(CpuSchedule, CountsTheCpuTimeThisThreadSpends) {
  const CpuSchedule before = cpu_schedule_now();
  ASSERT_TRUE(before.available) << "Linux has /proc/self/task/*/schedstat (CONFIG_SCHED_INFO)";
  // 20 ms of spinning: at least most of it is on a CPU, run or wait.
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
  volatile double x = 1.0;
  while (std::chrono::steady_clock::now() < until) x = std::sqrt(x + 1.0);
  const CpuSchedule d = cpu_schedule_between(before, cpu_schedule_now());
  EXPECT_TRUE(d.available);
  EXPECT_GT(double(d.run_ns + d.wait_ns), 15e6);
  EXPECT_GT(d.run_ns, 0u);
}

TEST(CpuSchedule, IntervalsClampWhereThreadsEnded) {
  CpuSchedule before{true, 500, 900}, after{true, 700, 400};  // a thread's counts left with it
  const CpuSchedule d = cpu_schedule_between(before, after);
  EXPECT_EQ(d.run_ns, 200u);
  EXPECT_EQ(d.wait_ns, 0u);
  EXPECT_FALSE(cpu_schedule_between(CpuSchedule{}, after).available);
}

TEST(CpuSchedule, WaitShareIsWaitOverWanted) {
  EXPECT_DOUBLE_EQ(cpu_wait_share({true, 300, 100}), 0.25);
  EXPECT_DOUBLE_EQ(cpu_wait_share({true, 0, 0}), 0.0);
}

}  // namespace
}  // namespace gi
