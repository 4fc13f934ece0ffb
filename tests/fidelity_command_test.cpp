// `giharness fidelity` end to end, against a small git repository the test
// builds: a release tag, a profile citing it, what --record writes, each kind
// of drift the command exists to report, and --ref's list of upstream changes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/test_support.h"

namespace gi {
namespace {

namespace fs = std::filesystem;
using test::run_command;
using test::run_giharness;

void write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

void git(const fs::path& repo, const std::string& args) {
  const auto r = run_command("git -C " + quoted(repo) +
                             " -c user.name=t -c user.email=t@t -c commit.gpgsign=false -c tag.gpgsign=false " + args);
  ASSERT_EQ(r.exit_code, 0) << args << "\n" << r.output;
}

const char* kShader = "// restir_di\nconst INITIAL_SAMPLES = 8u;\n\nfn spatial() {\n    let r = 30.0;\n}\n";

std::string profile_text(const std::string& source) {
  nlohmann::ordered_json doc = {
      {"name", "mini"},
      {"bevy_ref", "v9.0.0"},
      {"values", {{"restir_di.initial_samples", {{"value", 8}, {"source", source}}}}}};
  return doc.dump(2) + "\n";
}

class FidelityCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(repo());
    git(repo(), "init -q -b main");
    write(repo() / "crates/bevy_solari/src/realtime/restir_di.wgsl", kShader);
    git(repo(), "add -A");
    git(repo(), "commit -q -m release");
    git(repo(), "tag v9.0.0");
  }
  fs::path repo() const { return dir_.path() / "bevy"; }
  fs::path profile() const { return dir_.path() / "mini.json"; }
  test::CommandResult fidelity(const std::string& args = "") {
    return run_giharness("fidelity " + quoted(repo()) + " --profile " + quoted(profile()) + " " + args);
  }
  nlohmann::json cited() {
    std::ifstream in(profile());
    return nlohmann::json::parse(in)["values"]["restir_di.initial_samples"].value("cited", nlohmann::json::object());
  }
  test::TempDir dir_{"fidelity"};
};

TEST_F(FidelityCommand, RecordsThenHoldsEveryCitationToItsLines) {
  write(profile(), profile_text("v9.0.0:realtime/restir_di.wgsl:2 - INITIAL_SAMPLES = 8, the radius at :5"));
  auto r = fidelity();
  EXPECT_EQ(r.exit_code, 1) << r.output;  // nothing recorded yet
  EXPECT_NE(r.output.find("unrecorded"), std::string::npos) << r.output;

  r = fidelity("--record");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json c = cited();
  ASSERT_EQ(c.size(), 2u) << c.dump();
  EXPECT_TRUE(c.contains("v9.0.0:crates/bevy_solari/src/realtime/restir_di.wgsl:2")) << c.dump();
  EXPECT_TRUE(c.contains("v9.0.0:crates/bevy_solari/src/realtime/restir_di.wgsl:5")) << c.dump();

  const fs::path report = dir_.path() / "report.json";
  r = fidelity("--out " + quoted(report));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("0 drifted"), std::string::npos) << r.output;
  EXPECT_EQ(test::read_json(report)["drifted"], 0);

  // An edited line number is a citation nobody has read: unrecorded, and its
  // old fingerprint stale.
  write(profile(), profile_text("v9.0.0:realtime/restir_di.wgsl:3 - INITIAL_SAMPLES = 8, the radius at :5"));
  nlohmann::json keep = c;
  {
    std::ifstream in(profile());
    nlohmann::ordered_json doc = nlohmann::ordered_json::parse(in);
    doc["values"]["restir_di.initial_samples"]["cited"] = keep;
    std::ofstream(profile()) << doc.dump(2);
  }
  r = fidelity();
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("unrecorded restir_di.initial_samples"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stale restir_di.initial_samples"), std::string::npos) << r.output;
}

TEST_F(FidelityCommand, ATagThatMovedShowsAsMovedOrChanged) {
  write(profile(), profile_text("v9.0.0:realtime/restir_di.wgsl:2 and :5"));
  ASSERT_EQ(fidelity("--record").exit_code, 0);
  // The same tag name on other code (another repository, a re-tag): line 2
  // now holds other text, and line 5's text stands one line lower.
  write(repo() / "crates/bevy_solari/src/realtime/restir_di.wgsl",
        "// restir_di\nconst INITIAL_SAMPLES = 32u;\n\n\nfn spatial() {\n    let r = 30.0;\n}\n");
  git(repo(), "commit -q -am retag");
  git(repo(), "tag -f v9.0.0");
  const auto r = fidelity();
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("changed restir_di.initial_samples: v9.0.0:crates/bevy_solari/src/realtime/restir_di.wgsl:2"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("moved restir_di.initial_samples"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stands at lines 6"), std::string::npos) << r.output;
  // --record leaves a changed fingerprint as it was: a person reads it first.
  const nlohmann::json before = cited();
  EXPECT_EQ(fidelity("--record").exit_code, 1);
  EXPECT_EQ(cited(), before);
}

TEST_F(FidelityCommand, RefListsTheCommitsSinceTheReleaseAndWhatTheyDidToTheCitedLines) {
  write(profile(), profile_text("v9.0.0:realtime/restir_di.wgsl:2 and :5"));
  ASSERT_EQ(fidelity("--record").exit_code, 0);
  // Upstream: a commit that touches another file, then one that changes the
  // constant and moves the radius, then the shader language's rename.
  write(repo() / "crates/bevy_solari/src/lib.rs", "pub mod realtime;\n");
  git(repo(), "add -A");
  git(repo(), "commit -q -m unrelated");
  write(repo() / "crates/bevy_solari/src/realtime/restir_di.wgsl",
        "// restir_di\n// new\nconst INITIAL_SAMPLES = 32u;\n\nfn spatial() {\n    let r = 30.0;\n}\n");
  git(repo(), "commit -q -am 'Fewer samples'");
  git(repo(), "mv crates/bevy_solari/src/realtime/restir_di.wgsl crates/bevy_solari/src/realtime/restir_di.wesl");
  git(repo(), "commit -q -m 'WESL'");
  const auto r = fidelity("--ref main");
  EXPECT_EQ(r.exit_code, 0) << r.output;  // upstream's changes are news, not drift at the release
  EXPECT_NE(r.output.find("2 commits on main touch the 1 files"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Fewer samples"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("WESL"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("unrelated"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 changed, 1 moved"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("restir_di.initial_samples: 1 moved, 1 changed or gone"), std::string::npos) << r.output;
}

TEST_F(FidelityCommand, BadInputIsExitTwo) {
  write(profile(), profile_text("v9.0.0:realtime/restir_di.wgsl:2"));
  auto r = run_giharness("fidelity " + quoted(dir_.path() / "not-a-repo") + " --profile " + quoted(profile()));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("a git repository"), std::string::npos) << r.output;
  r = fidelity("--ref no-such-branch");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  // A citation of a file or lines the release does not have is drift.
  write(profile(), profile_text("v9.0.0:realtime/restir_di.wgsl:40 and realtime/gone.wgsl:1"));
  r = fidelity();
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("beyond the end"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no file realtime/gone.wgsl"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace gi
