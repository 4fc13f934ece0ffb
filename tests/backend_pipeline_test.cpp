// The full realtime pipeline (DI + ReSTIR GI into the world cache + specular)
// on both tracing backends: the same scenario, seed and frames with
// `--backend rayquery` and `--backend bvh`. The two backends return the same
// hits but t differs in its last bits (README, "Cross-check"), so the G-buffer
// depth, and through it GI's reservoirs and the cache, differ in last bits
// (measured: relMSE 6e-14 between the final images);
// the light tiles, DI and specular stay bit-identical. Stated tolerance: the
// final images' relMSE against each other below 1% of the per-frame
// relMSE against Embree (the pipeline's own noise), and the reference
// check's figures equal to 3 significant digits.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "core/exr_io.h"
#include "core/metrics.h"
#include "tests/test_support.h"

namespace gi {
namespace {

struct BackendRun {
  std::map<std::string, Image> layers;
  nlohmann::json reference;  // the reference check's compared frame
  nlohmann::json manifest;
};

BackendRun run_on(const std::string& backend, const std::filesystem::path& dir) {
  const auto out = dir / backend;
  const test::CommandResult r = test::run_giharness(
      "run " + (test::source_dir() / "scenarios/gi_cornell_box.json").string() + " --backend " + backend +
      " --capture 31 --out " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  BackendRun b;
  b.layers = read_exr(out / "captures/frame_00031/images.exr");
  b.manifest = test::read_json(out / "captures/frame_00031/manifest.json");
  const nlohmann::json summary = test::read_json(out / "summary.json");
  for (const auto& c : summary["checks"])
    if (c["name"] == "reference") b.reference = c["figures"]["frames"].back();
  return b;
}

// A buffer's hash in a capture manifest; a buffer missing from it fails the
// test (two missing buffers must not compare equal).
std::string hash_of(const nlohmann::json& manifest, const std::string& buffer, const std::string& side) {
  for (const auto& b : manifest["buffers"])
    if (b["name"] == buffer) return b["hash"];
  ADD_FAILURE() << "no buffer " << buffer << " in the " << side << " capture";
  return "missing from " + side;
}

TEST(BackendPipeline, FullRealtimeImagesAgreeBetweenRayQueryAndBvh) {
  GI_SKIP_WITHOUT_RAY_QUERY();
  test::TempDir dir("backend-pipeline");
  const BackendRun rq = run_on("rayquery", dir.path());
  const BackendRun bvh = run_on("bvh", dir.path());
  ASSERT_TRUE(rq.layers.count("") && bvh.layers.count(""));
  const double between = relmse(rq.layers.at(""), bvh.layers.at(""));
  const double per_frame = rq.reference["per_frame"]["relmse"].get<double>();
  std::printf("relMSE between backends %.3g; per-frame relMSE against Embree %.3g\n", between, per_frame);
  EXPECT_LT(between, 0.01 * per_frame);
  for (const char* figure : {"energy_ratio", "relmse"}) {
    const double a = rq.reference["temporal_mean"][figure], b = bvh.reference["temporal_mean"][figure];
    EXPECT_EQ(fmt::format("{:.3g}", a), fmt::format("{:.3g}", b)) << figure;
  }
  // Where the maths allows, bit-identical.
  for (const char* buffer : {"di/output", "di/stored_reservoirs", "specular/output", "world_cache/checksums"})
    EXPECT_EQ(hash_of(rq.manifest, buffer, "rayquery"), hash_of(bvh.manifest, buffer, "bvh")) << buffer;
}

}  // namespace
}  // namespace gi
