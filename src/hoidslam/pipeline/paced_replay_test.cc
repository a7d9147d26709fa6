#include "hoidslam/pipeline/paced_replay.h"

#include <algorithm>
#include <fstream>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"

namespace hoidslam::pipeline {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr int kWidth = 16, kHeight = 12;

// `count` frames 10 ms apart; frame i's colour is i everywhere, so a test can tell which frame it got.
io::RgbdSequence WriteFrames(const testing::TempDir& dir, int count) {
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  for (int i = 0; i < count; ++i) {
    const std::string name = fmt::format("{:03d}.png", i);
    cv::imwrite((dir / "rgb" / name).string(), cv::Mat(kHeight, kWidth, CV_8UC3, cv::Scalar::all(i)));
    cv::imwrite((dir / "depth" / name).string(), cv::Mat(kHeight, kWidth, CV_16UC1, cv::Scalar(5000)));
  }
  return io::RgbdSequence::OpenImageFolders(dir / "rgb", dir / "depth", 100.0);
}

constexpr std::size_t kFrameBytes = kWidth * kHeight * (3 + 4);  // BGR and depth in metres (float)

// Plays the whole replay, taking every frame handed out; returns their indices.
std::vector<std::size_t> PlayAll(PacedReplay& replay) {
  std::vector<std::size_t> got;
  for (std::optional<std::size_t> frame; (frame = replay.Next(frame, {}));) {
    const core::RgbdFrame image = replay.Take(*frame);
    EXPECT_EQ(image.rgb.at<cv::Vec3b>(0, 0)[0], *frame) << "frame " << *frame << " handed out another's image";
    EXPECT_FLOAT_EQ(image.depth.at<float>(0, 0), 1.0F);  // 5000 at TUM's factor 5000
    got.push_back(*frame);
  }
  return got;
}

TEST(PacedReplay, HandsOutEveryFrameThatIsNotDroppedDecodedAndInOrder) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = WriteFrames(dir, 20);
  PacedReplay replay(sequence, 20, std::size_t{1} << 20);
  const std::vector<std::size_t> got = PlayAll(replay);
  ASSERT_FALSE(got.empty());
  EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
  EXPECT_EQ(got.back(), 19U);
  EXPECT_EQ(got.size() + replay.dropped(), 20U);
  EXPECT_EQ(replay.chunks_decoded(), 1U);  // all of it fits the budget: decoded before the camera starts
}

TEST(PacedReplay, DecodesInChunksThatFitTheBudget) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = WriteFrames(dir, 20);
  PacedReplay replay(sequence, 15, 4 * kFrameBytes);  // the first 15 frames, 4 at a time
  const std::vector<std::size_t> got = PlayAll(replay);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back(), 14U);
  EXPECT_EQ(got.size() + replay.dropped(), 15U);
  // The clock stands still while a chunk is decoded, so decoding costs no frames: a chunk starts at frame 0, 4, 8
  // and 12 unless frames were dropped while the test itself was slow (then fewer, later chunks).
  EXPECT_GE(replay.chunks_decoded(), 2U);
  EXPECT_LE(replay.chunks_decoded(), 4U);
}

TEST(PacedReplay, ABudgetBelowOneFrameStillDecodesOneAtATime) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = WriteFrames(dir, 5);
  PacedReplay replay(sequence, 5, 1);
  const std::vector<std::size_t> got = PlayAll(replay);
  EXPECT_EQ(got.size() + replay.dropped(), 5U);
  EXPECT_EQ(replay.chunks_decoded(), got.size());
}

TEST(PacedReplay, AnUnreadableFrameIsReportedByItsFileBeforeTheCameraStarts) {
  const testing::TempDir dir;
  const io::RgbdSequence sequence = WriteFrames(dir, 8);
  std::ofstream(dir / "rgb" / "005.png") << "not a png";
  std::ofstream(dir / "rgb" / "006.png") << "not a png either";
  // The earliest broken frame is the one named, whichever decoding thread met it first.
  EXPECT_THAT([&] { PacedReplay(sequence, 8, std::size_t{1} << 20); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr((dir / "rgb" / "005.png").string())));
}

}  // namespace
}  // namespace hoidslam::pipeline
