// Where a run's time goes (core/phase_clock.h, replay/wall_breakdown.h) and
// the Embree reference cache key's sources (core/reference/sources_hash.cmake).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "core/phase_clock.h"
#include "replay/wall_breakdown.h"
#include "tests/test_support.h"

namespace gi {
namespace {

double seconds_of(const char* phase) {
  const auto all = phase_seconds();
  const auto it = all.find(phase);
  return it == all.end() ? 0.0 : it->second;
}

// A phase inside another counts once, in the inner one: the phases never add
// up to more than the wall time. (Counted in both, outer + inner would be
// about 0.01 + 2 x 0.05 s against a wall of 0.06 s.)
TEST(PhaseClock, ANestedPhaseCountsOnceInTheInnerOne) {
  const double outer_before = seconds_of("test_outer"), inner_before = seconds_of("test_inner");
  const auto start = std::chrono::steady_clock::now();
  {
    const PhaseScope outer("test_outer");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const PhaseScope inner("test_inner");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double outer = seconds_of("test_outer") - outer_before, inner = seconds_of("test_inner") - inner_before;
  EXPECT_GE(inner, 0.05);
  EXPECT_GE(outer, 0.01);
  EXPECT_LE(outer + inner, wall);
}

nlohmann::json frame(int index, double compiled_ms, double plain_ms) {
  return {{"frame", index}, {"pass_ms", {{"compiled", compiled_ms}, {"plain", plain_ms}}}};
}

// Frame 0's time above the median of the later frames, per pass: the
// compile at first dispatch; a pass no slower at frame 0 gets 0.
TEST(WallBreakdown, FirstDispatchIsFrameZeroAboveTheLaterFramesMedian) {
  const nlohmann::json frames = {frame(0, 1511.0, 5.0), frame(1, 12.0, 6.0), frame(2, 10.0, 5.5),
                                 frame(3, 11.0, 7.0)};
  const nlohmann::json b = wall_breakdown(2.0, frames);
  EXPECT_DOUBLE_EQ(b["first_dispatch_ms"]["compiled"].get<double>(), 1500.0);
  EXPECT_DOUBLE_EQ(b["first_dispatch_ms"]["plain"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(b["first_dispatch_seconds"].get<double>(), 1.5);
  EXPECT_TRUE(b["seconds"].contains("other"));
  // Two frames leave no later median to stand on.
  EXPECT_TRUE(wall_breakdown(2.0, {frame(0, 1010.0, 5.0), frame(1, 12.0, 6.0)})["first_dispatch_ms"].empty());
  EXPECT_NE(wall_breakdown_line(b).find("slowest first dispatch compiled 1.5 s"), std::string::npos);
}

// A process that runs several scenarios (run --seeds, sweep) reports each
// run's phases only: what earlier runs spent is not counted again.
TEST(WallBreakdown, ARunCountsOnlyItsOwnPhases) {
  {
    const PhaseScope earlier("test_run_phase");
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const auto at_start = phase_seconds();
  {
    const PhaseScope own("test_run_phase");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const double own = wall_breakdown(1.0, nlohmann::json::array(), at_start)["seconds"]["test_run_phase"].get<double>();
  EXPECT_GE(own, 0.01);
  EXPECT_LT(own, 0.2);  // without the snapshot it holds both runs' time, at least 0.21 s
}

// The nightly's total adds every run's figures.
TEST(WallBreakdown, TheSuiteTotalAddsTheRuns) {
  const nlohmann::json a = {{"wall_seconds", 3.0},
                            {"seconds", {{"frames", 2.0}, {"other", 1.0}}},
                            {"first_dispatch_ms", {{"x", 500.0}}},
                            {"first_dispatch_seconds", 0.5}};
  const nlohmann::json b = {{"wall_seconds", 5.0},
                            {"seconds", {{"frames", 1.0}, {"references", 4.0}}},
                            {"first_dispatch_ms", {{"x", 250.0}, {"y", 100.0}}},
                            {"first_dispatch_seconds", 0.35}};
  nlohmann::json total;
  add_wall_breakdown(total, a);
  add_wall_breakdown(total, b);
  add_wall_breakdown(total, nullptr);  // a run without a breakdown adds nothing
  EXPECT_EQ(total["runs"], 2);
  EXPECT_DOUBLE_EQ(total["wall_seconds"].get<double>(), 8.0);
  EXPECT_DOUBLE_EQ(total["seconds"]["frames"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(total["seconds"]["references"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(total["first_dispatch_ms"]["x"].get<double>(), 750.0);
  EXPECT_DOUBLE_EQ(total["first_dispatch_seconds"].get<double>(), 0.85);
}

// The reference cache key hashes its roots and what they include of
// core/shared and core/reference, transitively (relative includes beside the
// includer), and nothing else: an edit of a header the reference does not
// include keeps every cached reference, and so does an edit of a comment or
// of white space; an edit of the code of one it does, even two includes deep,
// renders them again.
class ReferenceSourcesHash : public ::testing::Test {
 protected:
  test::TempDir dir{"reference_sources_hash"};
  std::filesystem::path root() const { return dir.path(); }
  void write(const std::string& rel, const std::string& text) const {
    std::filesystem::create_directories((root() / rel).parent_path());
    std::ofstream(root() / rel) << text;
  }
  std::string hash() const {
    const std::filesystem::path out = root() / "out/hash.h";
    const std::string command = std::string(GIHARNESS_CMAKE) + " -DOUT=" + out.string() +
                                " -DROOTS=" + (root() / "core/reference/embree_x.cpp").string() +
                                " -DSOURCE_DIR=" + root().string() + " -P " +
                                (test::source_dir() / "core/reference/sources_hash.cmake").string() + " 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::ifstream in(out);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
};

TEST_F(ReferenceSourcesHash, FollowsTheIncludesAndNothingElse) {
  write("core/reference/embree_x.cpp", "#include \"core/shared/a.h\"\n#include <vector>\n");
  write("core/shared/a.h", "#include \"b.h\"\nint a;\n");
  write("core/shared/b.h", "int b;\n");
  write("core/shared/unrelated.h", "int u;\n");
  write("core/other.h", "int o;\n");
  const std::string first = hash();
  ASSERT_NE(first.find("GIHARNESS_REFERENCE_SOURCES_HASH"), std::string::npos);
  const std::string files = test::read_text(root() / "out/hash.h.files");
  EXPECT_NE(files.find("core/shared/b.h"), std::string::npos) << files;
  EXPECT_EQ(files.find("unrelated"), std::string::npos) << files;

  write("core/shared/unrelated.h", "int u2;\n");
  write("core/other.h", "int o2;\n");
  EXPECT_EQ(hash(), first);
  write("core/shared/b.h", "// why b is an int\nint   b;  // a comment\n\n");  // comments and layout only
  EXPECT_EQ(hash(), first);
  write("core/shared/b.h", "int b2;\n");  // two includes deep, relative to its includer
  const std::string second = hash();
  EXPECT_NE(second, first);
  write("core/reference/embree_x.cpp", "#include \"core/shared/a.h\"\n#include <vector>\nint edited;\n");
  EXPECT_NE(hash(), second);
}

}  // namespace
}  // namespace gi
