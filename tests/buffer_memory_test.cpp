// Buffer memory (gpu/buffer.h): device-local buffers moved through staging
// copies, as on a discrete GPU, against mapped ones, as on lavapipe. The
// staged path is forced on lavapipe with GIHARNESS_BUFFER_MEMORY=staged, so
// CI runs the code the H200 runs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/device.h"
#include "tests/test_support.h"

namespace gi {
namespace {

// A Device made with GIHARNESS_BUFFER_MEMORY set to `choice` (the variable is
// read when the device is made), restored afterwards.
gpu::Device device_with(const char* choice) {
  const char* old = std::getenv("GIHARNESS_BUFFER_MEMORY");
  const std::string saved = old ? old : "";
  setenv("GIHARNESS_BUFFER_MEMORY", choice, 1);
  gpu::Device device(std::nullopt, test::test_backend());
  if (old) setenv("GIHARNESS_BUFFER_MEMORY", saved.c_str(), 1);
  else unsetenv("GIHARNESS_BUFFER_MEMORY");
  return device;
}

TEST(BufferMemory, StagedBuffersUploadDownloadAndClearLikeMappedOnes) {
  for (const char* choice : {"staged", "mapped"}) {
    SCOPED_TRACE(choice);
    gpu::Device device = device_with(choice);
    const bool staged = std::string(choice) == "staged";
    EXPECT_EQ(device.staged_buffers(), staged);
    EXPECT_EQ(device.info().buffer_memory, choice);

    std::vector<std::uint32_t> words(4096);
    std::iota(words.begin(), words.end(), 7u);
    gpu::Buffer buffer(device, words.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "test words");
    EXPECT_EQ(buffer.staged(), staged);
    buffer.upload(words);
    EXPECT_EQ(buffer.download<std::uint32_t>(words.size()), words);
    // A slice: elements [1000, 1100).
    const auto slice = buffer.download<std::uint32_t>(100, 1000);
    EXPECT_EQ(slice, std::vector<std::uint32_t>(words.begin() + 1000, words.begin() + 1100));
    // Partial upload at an offset, then the whole buffer.
    const std::vector<std::uint32_t> patch = {1, 2, 3};
    buffer.upload(patch, 16 * 4);
    words[16] = 1, words[17] = 2, words[18] = 3;
    EXPECT_EQ(buffer.download<std::uint32_t>(words.size()), words);
    // Out of range is an error in both modes, before any copy.
    EXPECT_THROW(buffer.download<std::uint32_t>(2, words.size() - 1), std::exception);

    buffer.fill_zero();
    EXPECT_EQ(buffer.download<std::uint32_t>(words.size()), std::vector<std::uint32_t>(words.size(), 0u));
    buffer.upload(words);
    device.submit_and_wait([&](VkCommandBuffer cmd) { buffer.record_fill_zero(cmd); });
    EXPECT_EQ(buffer.download<std::uint32_t>(words.size()), std::vector<std::uint32_t>(words.size(), 0u));

    // A buffer larger than the staging buffer so far makes it grow.
    std::vector<std::uint32_t> big(3u << 18, 0xabcdef01u);
    gpu::Buffer large(device, big.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "test large");
    large.upload(big);
    EXPECT_EQ(large.download<std::uint32_t>(big.size()), big);
  }
}

TEST(BufferMemory, AStagedTransferWhileRecordingIsAnError) {
  gpu::Device device = device_with("staged");
  gpu::Buffer buffer(device, 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "test");
  // It would submit from inside a submission; record_fill_zero is the way.
  EXPECT_THROW(device.submit_and_wait([&](VkCommandBuffer) { buffer.fill_zero(); }), std::logic_error);
  buffer.fill_zero();  // the device is still usable
}

// The same run's bits either way: every per-frame image hash, every state
// buffer's hash after the last frame and the final image (realtime DI, ReSTIR
// GI, specular GI and the world cache).
TEST(BufferMemory, AStagedRunHasTheMappedRunsBits) {
  test::TempDir dir("buffer-memory");
  nlohmann::json summaries[2];
  const char* choices[2] = {"staged", "mapped"};
  for (int i = 0; i < 2; ++i) {
    const auto out = dir.path() / choices[i];
    const test::CommandResult r =
        test::run_giharness("run " + (test::source_dir() / "scenarios/gi_cornell_box.json").string() +
                                " --out " + out.string(),
                            std::string("GIHARNESS_BUFFER_MEMORY=") + choices[i]);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    summaries[i] = test::read_json(out / "summary.json");
    EXPECT_EQ(summaries[i]["device"]["buffer_memory"], choices[i]);
  }
  ASSERT_FALSE(summaries[0]["hashes"]["final_buffers"].empty());
  EXPECT_EQ(summaries[0]["hashes"], summaries[1]["hashes"]);
  EXPECT_EQ(summaries[0]["final_image_hash"], summaries[1]["final_image_hash"]);
}

// Observation reads back only what is judged: the frame record's
// measures are reduced on the GPU (gpu/passes/frame_output.h), so a frame no
// check judges downloads a few dozen bytes; a realtime reference check judging
// frame 12 alone reads both chains' temporal means on frame 12 and nothing on
// the others (summary.json's per-frame "transfers", counted by the device).
TEST(BufferMemory, ACheckJudgingOneFrameReadsBackOnlyOnThatFrame) {
  test::TempDir dir("buffer-memory-judged");
  nlohmann::json doc = test::read_json(test::source_dir() / "scenarios/di_cornell_box.json");
  doc.erase("$schema");
  doc["frames"] = 16;
  doc["resolution"] = {64, 36};
  doc["checks"] = {{{"name", "reference"}, {"frames", {12}}, {"spp", 16}}};
  const auto file = dir.path() / "judged.json";
  std::ofstream(file) << doc.dump(1);
  const auto out = dir.path() / "out";
  const test::CommandResult r = test::run_giharness("run " + file.string() + " --out " + out.string());
  // 16 spp at 64x36 judge frame 12 well within the reference check's noise (measured: relMSE 1.02x the
  // combined noise, energy 1.0006): it passes, and the run exits 0.
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(test::check_result(out, "reference").value("verdict", ""), "pass");
  const nlohmann::json frames = test::read_json(out / "summary.json").at("frames");
  ASSERT_EQ(frames.size(), 16u);
  const std::uint64_t image = 64u * 36u * 16u;  // one chain's DI signal, vec4 per pixel
  const std::uint64_t base = frames[1]["transfers"]["downloaded_bytes"];
  EXPECT_GT(base, 0u);
  EXPECT_LE(base, 256u) << "more than the frame's reduced measures";
  for (const nlohmann::json& f : frames) {
    const std::uint64_t bytes = f["transfers"]["downloaded_bytes"];
    if (f["frame"] == 12) EXPECT_GE(bytes, base + 2 * image) << "frame 12 reads both chains' means";
    // The last frame also hashes the final state on the GPU: 8 bytes per buffer.
    else if (f["frame"] == 15) EXPECT_LE(bytes, base + 8 * 32) << "frame 15";
    else EXPECT_EQ(bytes, base) << "frame " << f["frame"];
    // Only the judged frame (it reads buffers) and the last are observed
    // before the next frame is submitted; the rest while the GPU renders it.
    const bool at_once = f["frame"] == 12 || f["frame"] == 15;
    EXPECT_EQ(f["observed_during_next_frame"], !at_once) << "frame " << f["frame"];
  }
}

TEST(BufferMemory, AnUnknownChoiceIsBadInput) {
  test::TempDir dir("buffer-memory-bad");
  const test::CommandResult r = test::run_giharness(
      "run " + (test::source_dir() / "scenarios/di_cornell_box.json").string() + " --out " + dir.path().string(),
      "GIHARNESS_BUFFER_MEMORY=vram");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("GIHARNESS_BUFFER_MEMORY"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("staged or mapped"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
