#include "app/child_process.h"

#include <chrono>
#include <csignal>
#include <cstring>
#include <deque>
#include <fstream>
#include <thread>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/errors.h"

namespace gi {

std::filesystem::path self_executable() { return std::filesystem::read_symlink("/proc/self/exe"); }

std::string signal_name(int signal) {
  switch (signal) {
    case SIGSEGV: return "SIGSEGV";
    case SIGABRT: return "SIGABRT";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGILL: return "SIGILL";
    case SIGKILL: return "SIGKILL";
    case SIGTERM: return "SIGTERM";
    case SIGINT: return "SIGINT";
    default: return "signal " + std::to_string(signal);
  }
}

std::string tail_of_file(const std::filesystem::path& file, std::size_t lines) {
  std::ifstream in(file, std::ios::binary);
  std::deque<std::string> last;
  for (std::string line; std::getline(in, line);) {
    last.push_back(line.size() > 2000 ? line.substr(0, 2000) + " …" : line);
    if (last.size() > lines) last.pop_front();
  }
  std::string text;
  for (const std::string& l : last) text += l + "\n";
  return text;
}

ChildEnd run_child(const std::vector<std::string>& argv, const std::filesystem::path& log, const ChildLimits& limits,
                   const std::function<bool()>& abandon) {
  // Everything the child needs is prepared before fork: between fork and exec
  // only async-signal-safe calls are allowed.
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string log_path = log.string();
  const pid_t parent = ::getpid();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw DeviceError(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);  // the nightly died before prctl
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) ::_exit(127);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    if (limits.memory_bytes) {
      const rlimit r{*limits.memory_bytes, *limits.memory_bytes};
      ::setrlimit(RLIMIT_AS, &r);
    }
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here, so the group exists before any kill below

  ChildEnd end;
  bool terminated = false;
  std::chrono::steady_clock::time_point term_sent;
  for (;;) {
    int status = 0;
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    const auto now = std::chrono::steady_clock::now();
    end.seconds = std::chrono::duration<double>(now - start).count();
    if (done == pid) {
      if (end.how == ChildEnd::How::exited) {  // not already marked timed out or abandoned
        if (WIFEXITED(status)) {
          end.exit_code = WEXITSTATUS(status);
        } else if (WIFSIGNALED(status)) {
          end.how = ChildEnd::How::signalled;
          end.signal = WTERMSIG(status);
        }
      }
      return end;
    }
    if (done < 0 && errno != EINTR) throw DeviceError(std::string("waitpid failed: ") + std::strerror(errno));
    if (end.how == ChildEnd::How::exited && abandon && abandon()) {
      end.how = ChildEnd::How::abandoned;
      ::kill(-pid, SIGKILL);
    } else if (end.how == ChildEnd::How::exited && end.seconds > limits.wall_seconds) {
      end.how = ChildEnd::How::timed_out;
      ::kill(-pid, SIGTERM);
      terminated = true;
      term_sent = now;
    } else if (terminated && now - term_sent > std::chrono::seconds(5)) {
      ::kill(-pid, SIGKILL);
      terminated = false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace gi
