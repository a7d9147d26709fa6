#include "hoidslam/io/atomic_file.h"

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::io {
namespace {

using ::hoidslam::testing::ReadText;


std::size_t CountEntries(const std::filesystem::path& folder) {
  return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(folder), {}));
}

TEST(AtomicFile, AppearsOnlyOnCommit) {
  testing::TempDir dir;
  const auto path = dir / "out.txt";
  AtomicFile file(path);
  file.stream() << "complete\n";
  EXPECT_FALSE(std::filesystem::exists(path));
  file.Commit();
  EXPECT_EQ(ReadText(path), "complete\n");
  EXPECT_EQ(CountEntries(dir.path()), 1U);
}

TEST(AtomicFile, AbandonedWriteLeavesOldFileAndNoDebris) {
  testing::TempDir dir;
  const auto path = dir / "out.txt";
  std::ofstream(path) << "old\n";
  try {
    AtomicFile file(path);
    file.stream() << "half of the new";
    throw std::runtime_error("interrupted");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(ReadText(path), "old\n");
  EXPECT_EQ(CountEntries(dir.path()), 1U);
}

TEST(AtomicFile, MissingFolderIsNamed) {
  testing::TempDir dir;
  try {
    AtomicFile file(dir / "no-such-folder" / "out.txt");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-folder/out.txt"), std::string::npos);
  }
}

// The message of the InputError CheckWritableFile throws for `path`, or "" when it throws none.
std::string WritableFileError(const std::filesystem::path& path) {
  try {
    CheckWritableFile(path, "--save-map");
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CheckWritableFile, AcceptsANewOrExistingFileInAFolderAndLeavesNothingBehind) {
  testing::TempDir dir;
  EXPECT_EQ(WritableFileError(dir / "new.hmap"), "");
  EXPECT_EQ(CountEntries(dir.path()), 0U);
  std::ofstream(dir / "old.hmap") << "old\n";
  EXPECT_EQ(WritableFileError(dir / "old.hmap"), "");
  EXPECT_EQ(ReadText(dir / "old.hmap"), "old\n");
  EXPECT_EQ(CountEntries(dir.path()), 1U);
}

TEST(CheckWritableFile, NamesTheParameterAndTheFileOfAMissingFolderOrAFolder) {
  testing::TempDir dir;
  const auto missing = dir / "no-such-folder" / "map.hmap";
  const std::string missing_error = WritableFileError(missing);
  EXPECT_EQ(missing_error.rfind("parameter --save-map: cannot write " + missing.string(), 0), 0U) << missing_error;
  EXPECT_NE(missing_error.find("no-such-folder does not exist"), std::string::npos) << missing_error;
  const std::string folder_error = WritableFileError(dir.path());
  EXPECT_EQ(folder_error.rfind("parameter --save-map: " + dir.path().string() + " is a folder", 0), 0U) << folder_error;
  EXPECT_FALSE(std::filesystem::exists(dir / "no-such-folder"));
}

TEST(WriteImageAtomically, WritesSixteenBitPngExactly) {
  testing::TempDir dir;
  cv::Mat depth(4, 5, CV_16UC1);
  for (int i = 0; i < depth.rows * depth.cols; ++i) depth.at<std::uint16_t>(i) = static_cast<std::uint16_t>(i * 1000);
  WriteImageAtomically(dir / "d.png", depth);
  const cv::Mat read = cv::imread((dir / "d.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(read.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(read, depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(CountEntries(dir.path()), 1U);
}

TEST(WriteImageAtomically, FailureLeavesNothing) {
  testing::TempDir dir;
  EXPECT_THROW(WriteImageAtomically(dir / "missing" / "x.png", cv::Mat(2, 2, CV_8UC3)), core::InputError);
  EXPECT_THROW(WriteImageAtomically(dir / "x.unknownformat", cv::Mat(2, 2, CV_8UC3)), core::InputError);
  EXPECT_EQ(CountEntries(dir.path()), 0U);
}

TEST(AtomicFolder, AppearsOnlyOnCommitAndReplacesTheOldOneThen) {
  testing::TempDir dir;
  const auto out = dir / "seq";
  std::filesystem::create_directories(out);
  std::ofstream(out / "old.txt") << "old\n";
  EXPECT_THROW(AtomicFolder(out, false, "--out", "use --force"), core::InputError);
  {
    AtomicFolder folder(out, true, "--out", "use --force");
    std::ofstream(folder.temporary() / "new.txt") << "new\n";
    EXPECT_EQ(ReadText(out / "old.txt"), "old\n");  // untouched until the commit
    folder.Commit();
  }
  EXPECT_FALSE(std::filesystem::exists(out / "old.txt"));
  EXPECT_EQ(ReadText(out / "new.txt"), "new\n");
  EXPECT_EQ(CountEntries(dir.path()), 1U);  // no temporary or old folder left
}

TEST(AtomicFolder, AbandonedFolderLeavesNothingAndKeepsTheOldOne) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "seq");
  std::ofstream(dir / "seq" / "old.txt") << "old\n";
  {
    AtomicFolder folder(dir / "seq/", true, "--out", "use --force");  // a trailing separator names the same folder
    EXPECT_EQ(folder.path().filename(), "seq");
    std::ofstream(folder.temporary() / "half.txt") << "half";
  }
  EXPECT_EQ(ReadText(dir / "seq" / "old.txt"), "old\n");
  EXPECT_EQ(CountEntries(dir.path()), 1U);
}

TEST(AtomicFolder, RemovesTheStagingFolderOfAKilledJobAndNoOther) {
  testing::TempDir dir;
  // The pid of a process that has ended, as a job killed mid-run leaves it.
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  const auto stale = dir / fmt::format("run.partial-{}", child);
  const auto running = dir / "run.partial-1";  // pid 1 runs as long as the machine does
  const auto other = dir / fmt::format("walk.partial-{}", child);  // another folder's
  for (const auto& folder : {stale, running, other}) {
    std::filesystem::create_directories(folder);
    std::ofstream(folder / "frames.jsonl") << "{}\n";
  }
  AtomicFolder folder(dir / "run", false, "--out", "use --force");
  EXPECT_EQ(folder.stale_removed(), std::vector<std::filesystem::path>{stale});
  EXPECT_FALSE(std::filesystem::exists(stale));
  EXPECT_TRUE(std::filesystem::exists(running));
  EXPECT_TRUE(std::filesystem::exists(other));
}

TEST(AtomicFolder, RefusesTheWorkingDirectoryAndItsAncestors) {
  const std::filesystem::path cwd = std::filesystem::current_path();
  for (const std::filesystem::path& path : {cwd, cwd / ".", cwd.parent_path(), std::filesystem::path("/")}) {
    try {
      AtomicFolder folder(path, true, "--out", "use --force");
      FAIL() << path;
    } catch (const core::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("parameter --out"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace hoidslam::io
