#include "core/phase_clock.h"

#include <mutex>

namespace gi {
namespace {

std::mutex g_mutex;
std::map<std::string, double> g_seconds;
thread_local PhaseScope* t_innermost = nullptr;

}  // namespace

std::map<std::string, double> phase_seconds() {
  std::lock_guard lock(g_mutex);
  return g_seconds;
}

PhaseScope::PhaseScope(const char* phase)
    : phase_(phase), start_(std::chrono::steady_clock::now()), outer_(t_innermost) {
  t_innermost = this;
}

PhaseScope::~PhaseScope() {
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  t_innermost = outer_;
  if (outer_) outer_->nested_seconds_ += total;
  std::lock_guard lock(g_mutex);
  g_seconds[phase_] += total - nested_seconds_;
}

}  // namespace gi
