// Replays every fuzz target over its corpus and regressions (fuzz/corpus/<target>, fuzz/regressions/<target>)
// in the ordinary test build, without libFuzzer: the crashes fuzzing found stay fixed, and the inputs that
// reach deep into each parser are run on every test run.

#include <algorithm>
#include <exception>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fuzz/targets.h"
#include "support/text_file.h"

namespace hoidslam::fuzz {

// Names the target in gtest's output (found by argument-dependent lookup, so beside Target).
void PrintTo(const Target& target, std::ostream* out) { *out << target.name; }

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> FilesIn(const fs::path& folder) {
  std::vector<fs::path> files;
  if (!fs::is_directory(folder)) return files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

class Replay : public ::testing::TestWithParam<Target> {};

TEST_P(Replay, CorpusAndRegressionsKeepTheContract) {
  const Target& target = GetParam();
  const fs::path fuzz_dir = HOIDSLAM_FUZZ_DIR;
  const std::vector<fs::path> corpus = FilesIn(fuzz_dir / "corpus" / target.name);
  ASSERT_FALSE(corpus.empty()) << "no corpus in " << (fuzz_dir / "corpus" / target.name);
  std::vector<fs::path> inputs = corpus;
  const std::vector<fs::path> regressions = FilesIn(fuzz_dir / "regressions" / target.name);
  inputs.insert(inputs.end(), regressions.begin(), regressions.end());
  for (const fs::path& input : inputs) {
    const std::string bytes = testing::ReadText(input);
    try {
      target.run({reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()});
    } catch (const std::exception& e) {
      ADD_FAILURE() << input << ": " << e.what();
    }
  }
}

// The fuzz build makes one program per corpus folder (fuzz/CMakeLists.txt), named after a target.
TEST(Corpus, EveryFolderNamesATarget) {
  for (const fs::directory_entry& folder : fs::directory_iterator(fs::path(HOIDSLAM_FUZZ_DIR) / "corpus")) {
    EXPECT_NO_THROW(FindTarget(folder.path().filename().string())) << folder.path();
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, Replay, ::testing::ValuesIn(Targets().begin(), Targets().end()),
                         [](const ::testing::TestParamInfo<Target>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace hoidslam::fuzz
