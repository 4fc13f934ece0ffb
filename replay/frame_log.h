// Per-frame records of a run, with memory that stays bounded however long the
// run is (a 100 000-frame soak must not grow): every record is streamed to
// <out>/frames.jsonl (one JSON object a line, renamed into place when the run
// ends), and a decimated copy is kept for summary.json and the report —
// every record up to `capacity`, then every 2nd, 4th, … (the stride doubles
// each time the copy fills), plus always the last record.
#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include <nlohmann/json.hpp>

namespace gi {

class FrameLog {
 public:
  FrameLog(std::filesystem::path file, std::size_t capacity = 4096);
  ~FrameLog();

  void add(const nlohmann::json& record);
  // Flushes and renames frames.jsonl into place.
  void finish();

  // The kept records in order, the last one included.
  nlohmann::json kept() const;
  std::uint64_t count() const { return count_; }
  std::uint64_t stride() const { return stride_; }
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_, tmp_;
  std::ofstream out_;
  std::size_t capacity_;
  std::uint64_t count_ = 0;
  std::uint64_t stride_ = 1;
  std::vector<std::pair<std::uint64_t, nlohmann::json>> kept_;  // (sequence number, record)
  nlohmann::json last_;
  bool finished_ = false;
};

}  // namespace gi
