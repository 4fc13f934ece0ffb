// Reads a git repository (a clone or a bare mirror) through the git command:
// a file as it is at a ref, and the commits between two refs. The fidelity
// command reads Bevy's source with it.
#pragma once
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gi {

struct GitCommit {
  std::string hash, date, subject;  // short hash, YYYY-MM-DD
  std::vector<std::string> files;   // the paths of the query it touches
};

class GitReader {
 public:
  // InputError (exit 2) when `repository` is not a git repository or git is
  // not on PATH.
  explicit GitReader(std::filesystem::path repository);

  // The file's text at `ref`; nullopt when the ref or the file does not exist.
  // Cached: each (ref, path) is read once.
  const std::optional<std::string>& file_at(const std::string& ref, const std::string& path);

  // The full hash `ref` names, or nullopt. Cached: each ref is asked once.
  const std::optional<std::string>& resolve(const std::string& ref);

  // Commits reachable from `to` and not from `from` that touch any of
  // `paths`, newest first.
  std::vector<GitCommit> commits_between(const std::string& from, const std::string& to,
                                         const std::vector<std::string>& paths);

 private:
  // git's exit code and its standard output.
  std::pair<int, std::string> git(const std::vector<std::string>& args) const;

  std::filesystem::path repository_;
  std::map<std::pair<std::string, std::string>, std::optional<std::string>> files_;
  std::map<std::string, std::optional<std::string>> refs_;
};

}  // namespace gi
