// One nightly scenario in a process of its own: whatever it does
// (a crash, an abort, a runaway allocation, a hung or lost GPU), the night
// goes on. CTest, Falcor's image tests and CI farms isolate tests the same way.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace gi {

struct ChildLimits {
  double wall_seconds = 3600.0;                // then SIGTERM, and SIGKILL 5 s later
  std::optional<std::uint64_t> memory_bytes;  // RLIMIT_AS of the child
};

struct ChildEnd {
  enum class How { exited, signalled, timed_out, abandoned } how = How::exited;
  int exit_code = -1;  // How::exited
  int signal = 0;      // How::signalled
  double seconds = 0.0;
};

// Runs argv (argv[0] an executable path) with its stdout and stderr written
// to `log`, in a process group of its own (a Ctrl-C at the terminal reaches
// the nightly, which lets the child finish), killed if this process dies.
// `abandon` is polled while it runs; true kills it at once.
ChildEnd run_child(const std::vector<std::string>& argv, const std::filesystem::path& log, const ChildLimits& limits,
                   const std::function<bool()>& abandon);

// "SIGSEGV" for 11; "signal N" for one without a name.
std::string signal_name(int signal);

// The last `lines` lines of a text file (empty if unreadable).
std::string tail_of_file(const std::filesystem::path& file, std::size_t lines);

// This executable (/proc/self/exe).
std::filesystem::path self_executable();

}  // namespace gi
