// core/data_dir.h: the lookup order of giharness's run-time data folder.
// (The installed binary itself: tests/install_test.sh.)
#include "core/data_dir.h"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace {

// A folder that passes for a data folder: what the lookup checks for.
void make_data_dir(const fs::path& dir) {
  fs::create_directories(dir / "gpu" / "shaders");
  fs::create_directories(dir / "scenarios" / "profiles");
}

std::string message_of(const char* env, const fs::path& exe) {
  try {
    gi::find_data_dir(env, exe);
  } catch (const gi::DataDirError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(DataDir, InstalledLayoutIsFoundFromTheBinary) {
  gi::test::TempDir t("data-dir");
  make_data_dir(t.path() / "share" / "giharness");
  EXPECT_EQ(gi::find_data_dir(nullptr, t.path() / "bin" / "giharness"), t.path() / "share" / "giharness");
}

TEST(DataDir, BuildTreeLayoutIsFoundBesideTheBinary) {
  gi::test::TempDir t("data-dir");
  make_data_dir(t.path() / "share" / "giharness");
  EXPECT_EQ(gi::find_data_dir(nullptr, t.path() / "giharness"), t.path() / "share" / "giharness");
}

TEST(DataDir, TheVariableWinsAndLosesItsTrailingSlash) {
  gi::test::TempDir t("data-dir");
  make_data_dir(t.path() / "share" / "giharness");
  make_data_dir(t.path() / "mine");
  const std::string env = (t.path() / "mine").string() + "/";
  EXPECT_EQ(gi::find_data_dir(env.c_str(), t.path() / "bin" / "giharness"), t.path() / "mine");
  // Empty counts as unset.
  EXPECT_EQ(gi::find_data_dir("", t.path() / "bin" / "giharness"), t.path() / "share" / "giharness");
}

TEST(DataDir, AWrongVariableIsAnErrorNotAFallback) {
  gi::test::TempDir t("data-dir");
  make_data_dir(t.path() / "share" / "giharness");
  const std::string env = (t.path() / "typo").string();
  const std::string msg = message_of(env.c_str(), t.path() / "bin" / "giharness");
  EXPECT_NE(msg.find("GIHARNESS_DATA_DIR=" + env), std::string::npos) << msg;
}

TEST(DataDir, NothingFoundNamesEveryPlaceTried) {
  gi::test::TempDir t("data-dir");
  fs::create_directories(t.path() / "share" / "giharness" / "gpu" / "shaders");  // no profiles: not a data folder
  const std::string msg = message_of(nullptr, t.path() / "bin" / "giharness");
  EXPECT_NE(msg.find((t.path() / "share" / "giharness").string()), std::string::npos) << msg;
  EXPECT_NE(msg.find((t.path() / "bin" / "share" / "giharness").string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("GIHARNESS_DATA_DIR"), std::string::npos) << msg;
}

// The test binary (<build>/tests/) finds the build tree's symlinked folder,
// whose files are the source tree's.
TEST(DataDir, TheTestBinaryFindsTheBuildTreesFolder) {
  const fs::path& dir = gi::data_dir();
  EXPECT_TRUE(fs::exists(dir / "scenarios" / "profiles" / "solari-0.18.json")) << dir;
  EXPECT_TRUE(fs::equivalent(dir / "gpu" / "shaders", gi::test::source_dir() / "gpu" / "shaders")) << dir;
}
