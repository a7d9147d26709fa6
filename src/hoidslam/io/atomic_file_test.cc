#include "hoidslam/io/atomic_file.h"

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"

namespace hoidslam::io {
namespace {

std::string ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

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
  EXPECT_EQ(ReadAll(path), "complete\n");
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
  EXPECT_EQ(ReadAll(path), "old\n");
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

}  // namespace
}  // namespace hoidslam::io
