#include "replay/frame_log.h"

#include <stdexcept>

#include <unistd.h>

namespace gi {

FrameLog::FrameLog(std::filesystem::path file, std::size_t capacity)
    : file_(std::move(file)), capacity_(capacity < 2 ? 2 : capacity) {
  if (file_.has_parent_path()) std::filesystem::create_directories(file_.parent_path());
  tmp_ = file_;
  tmp_ += ".tmp." + std::to_string(::getpid());
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write " + tmp_.string());
}

FrameLog::~FrameLog() {
  // A run that ended in an exception leaves no frames.jsonl, only nothing:
  // the partial stream is removed rather than passed off as complete.
  if (!finished_) {
    out_.close();
    std::error_code ec;
    std::filesystem::remove(tmp_, ec);
  }
}

void FrameLog::add(const nlohmann::json& record) {
  out_ << record.dump() << '\n';
  if (count_ % stride_ == 0) {
    kept_.emplace_back(count_, record);
    if (kept_.size() > capacity_) {
      stride_ *= 2;
      std::vector<std::pair<std::uint64_t, nlohmann::json>> thinned;
      thinned.reserve(capacity_ / 2 + 1);
      for (auto& k : kept_)
        if (k.first % stride_ == 0) thinned.push_back(std::move(k));
      kept_ = std::move(thinned);
    }
  }
  last_ = record;
  ++count_;
}

void FrameLog::finish() {
  if (finished_) return;
  out_.flush();
  out_.close();
  if (!out_) throw std::runtime_error("cannot write " + tmp_.string());
  std::filesystem::rename(tmp_, file_);
  finished_ = true;
}

nlohmann::json FrameLog::kept() const {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& k : kept_) a.push_back(k.second);
  if (count_ > 0 && (kept_.empty() || kept_.back().first != count_ - 1)) a.push_back(last_);
  return a;
}

}  // namespace gi
