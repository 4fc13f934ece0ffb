// Replays the committed fuzz corpus (tests/fuzz/corpus/) through the fuzz
// targets: every input must end in success or a gi::InputError, nothing else.
// The long runs (≥ 1 000 000 executions per target, sanitizers on) are
// `.ci/fuzz`; this keeps the inputs they found interesting from regressing.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "tests/fuzz/fuzz_targets.h"
#include "tests/test_support.h"

namespace gi {
namespace {

std::vector<std::filesystem::path> corpus(const char* name) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(test::source_dir() / "tests/fuzz/corpus" / name))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

void replay(const char* name, void (*target)(const std::uint8_t*, std::size_t)) {
  const auto files = corpus(name);
  ASSERT_GE(files.size(), 5u) << "the corpus should hold the seeds at least";
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    SCOPED_TRACE(f.filename().string());
    EXPECT_NO_THROW(target(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
  }
}

TEST(FuzzCorpus, ScenarioInputsEndInSuccessOrInputError) { replay("scenario", &fuzz::scenario_input); }
TEST(FuzzCorpus, GltfInputsEndInSuccessOrInputError) { replay("gltf", &fuzz::gltf_input); }

}  // namespace
}  // namespace gi
