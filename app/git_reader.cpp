#include "app/git_reader.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <sstream>

#include "core/errors.h"

extern char** environ;

namespace gi {

GitReader::GitReader(std::filesystem::path repository) : repository_(std::move(repository)) {
  const auto [code, out] = git({"rev-parse", "--git-dir"});
  if (code != 0)
    throw InputError(repository_.string(), "", "a git repository (a clone or a bare mirror of Bevy) and git on PATH");
}

std::pair<int, std::string> GitReader::git(const std::vector<std::string>& args) const {
  std::vector<std::string> argv = {"git", "-C", repository_.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> c_argv;
  for (std::string& a : argv) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);

  int pipe_fd[2];
  if (::pipe(pipe_fd) != 0) return {-1, {}};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fd[1], STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addclose(&actions, pipe_fd[0]);
  posix_spawn_file_actions_addclose(&actions, pipe_fd[1]);
  pid_t pid = 0;
  const int spawned = ::posix_spawnp(&pid, "git", &actions, nullptr, c_argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fd[1]);
  std::string out;
  if (spawned == 0) {
    std::array<char, 65536> buf;
    for (;;) {
      const ssize_t n = ::read(pipe_fd[0], buf.data(), buf.size());
      if (n > 0) {
        out.append(buf.data(), static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        break;
      }
    }
  }
  ::close(pipe_fd[0]);
  if (spawned != 0) return {-1, {}};
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, std::move(out)};
}

const std::optional<std::string>& GitReader::file_at(const std::string& ref, const std::string& path) {
  const auto key = std::make_pair(ref, path);
  auto it = files_.find(key);
  if (it == files_.end()) {
    auto [code, out] = git({"show", ref + ":" + path});
    it = files_.emplace(key, code == 0 ? std::optional<std::string>(std::move(out)) : std::nullopt).first;
  }
  return it->second;
}

const std::optional<std::string>& GitReader::resolve(const std::string& ref) {
  auto it = refs_.find(ref);
  if (it == refs_.end()) {
    auto [code, out] = git({"rev-parse", "--verify", "--quiet", ref + "^{commit}"});
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    it = refs_.emplace(ref, code == 0 ? std::optional<std::string>(std::move(out)) : std::nullopt).first;
  }
  return it->second;
}

std::vector<GitCommit> GitReader::commits_between(const std::string& from, const std::string& to,
                                                  const std::vector<std::string>& paths) {
  // One record per commit: \x1e, then hash, date and subject on a line, then
  // the touched paths (--name-only), one per line.
  std::vector<std::string> args = {"log", "--format=%x1e%h%x09%ad%x09%s", "--date=short", "--name-only",
                                   from + ".." + to, "--"};
  args.insert(args.end(), paths.begin(), paths.end());
  const auto [code, out] = git(args);
  std::vector<GitCommit> commits;
  if (code != 0) return commits;
  std::size_t start = 0;
  while ((start = out.find('\x1e', start)) != std::string::npos) {
    const std::size_t end = out.find('\x1e', start + 1);
    std::istringstream record(out.substr(start + 1, end == std::string::npos ? std::string::npos : end - start - 1));
    std::string header;
    std::getline(record, header);
    GitCommit c;
    const std::size_t t1 = header.find('\t'), t2 = header.find('\t', t1 + 1);
    c.hash = header.substr(0, t1);
    c.date = header.substr(t1 + 1, t2 - t1 - 1);
    c.subject = header.substr(t2 + 1);
    for (std::string line; std::getline(record, line);)
      if (!line.empty()) c.files.push_back(line);
    commits.push_back(std::move(c));
    start = end == std::string::npos ? out.size() : end;
  }
  return commits;
}

}  // namespace gi
