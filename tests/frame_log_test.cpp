// FrameLog keeps memory bounded over any run length and loses no record on disk.
#include <gtest/gtest.h>

#include <fstream>

#include "replay/frame_log.h"
#include "tests/test_support.h"

namespace gi {
namespace {

TEST(FrameLog, StreamsEveryRecordAndKeepsABoundedRegularSubsample) {
  test::TempDir dir("frame-log");
  const auto file = dir.path() / "frames.jsonl";
  FrameLog log(file, /*capacity=*/8);
  for (int i = 0; i < 100; ++i) log.add({{"frame", i}});
  EXPECT_FALSE(std::filesystem::exists(file)) << "renamed into place only when complete";
  log.finish();

  std::ifstream in(file);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) EXPECT_EQ(nlohmann::json::parse(line)["frame"], n++);
  EXPECT_EQ(n, 100);

  // 100 records through a capacity of 8: the stride doubled to 16, so frames
  // 0, 16, …, 96 are kept, then the last one, 99.
  const nlohmann::json kept = log.kept();
  EXPECT_EQ(log.stride(), 16u);
  ASSERT_EQ(kept.size(), 8u);
  for (std::size_t i = 0; i + 1 < kept.size(); ++i) EXPECT_EQ(kept[i]["frame"], 16 * static_cast<int>(i));
  EXPECT_EQ(kept.back()["frame"], 99);
}

TEST(FrameLog, KeepsEverythingBelowCapacity) {
  test::TempDir dir("frame-log-small");
  FrameLog log(dir.path() / "frames.jsonl", 8);
  for (int i = 0; i < 8; ++i) log.add({{"frame", i}});
  log.finish();
  EXPECT_EQ(log.kept().size(), 8u);
  EXPECT_EQ(log.stride(), 1u);
}

TEST(FrameLog, StaysBoundedOverAMillionRecords) {
  test::TempDir dir("frame-log-long");
  FrameLog log(dir.path() / "frames.jsonl", 64);
  for (int i = 0; i < 1'000'000; ++i) log.add(i);
  EXPECT_LE(log.kept().size(), 65u);
  EXPECT_EQ(log.count(), 1'000'000u);
}

TEST(FrameLog, AnAbandonedRunLeavesNoFile) {
  test::TempDir dir("frame-log-abandoned");
  {
    FrameLog log(dir.path() / "frames.jsonl");
    log.add(1);
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace gi
