#include "hoidslam/detect/file_detector.h"

#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"

namespace hoidslam::detect {
namespace {

using ::testing::HasSubstr;

constexpr double kFirst = 1341846313.592026;
constexpr double kSecond = 1341846316.570121;

// Writes a two-frame file for sequence "walking_xyz" on 640×480 images: a person and a cup, then nothing.
std::filesystem::path WriteTwoFrames(const hoidslam::testing::TempDir& dir) {
  const std::filesystem::path path = dir / "detections.jsonl";
  io::DetectionsFileWriter writer(path, {"walking_xyz", "yolox_nano.onnx", 640, 480});
  writer.Write(
      {kFirst, {{0, "person", 0.91F, {100.5F, 20.25F, 200.0F, 400.0F}}, {41, "cup", 0.5F, {300, 200, 30, 40}}}});
  writer.Write({kSecond, {}});
  writer.Commit();
  return path;
}

TEST(FileDetector, ReplaysWhatWasWritten) {
  hoidslam::testing::TempDir dir;
  FileDetector detector(WriteTwoFrames(dir));
  const cv::Mat image(480, 640, CV_8UC3);
  const auto first = detector.Detect(kFirst, image);
  ASSERT_EQ(first.size(), 2U);
  EXPECT_EQ(first[0].label, "person");
  EXPECT_EQ(first[0].class_id, 0);
  EXPECT_FLOAT_EQ(first[0].score, 0.91F);
  EXPECT_FLOAT_EQ(first[0].box.x, 100.5F);
  EXPECT_FLOAT_EQ(first[0].box.y, 20.25F);
  EXPECT_FLOAT_EQ(first[0].box.width, 200.0F);
  EXPECT_FLOAT_EQ(first[0].box.height, 400.0F);
  EXPECT_EQ(first[1].label, "cup");
  EXPECT_EQ(first[1].class_id, 41);
  EXPECT_TRUE(detector.Detect(kSecond, image).empty());
  // Microsecond rounding of the timestamp still finds the frame.
  EXPECT_EQ(detector.Detect(kFirst + 2e-6, cv::Mat()).size(), 2U);
  EXPECT_EQ(detector.Name(), "yolox_nano.onnx");
}

TEST(FileDetector, MissingTimestampIsAnInputErrorNamingTheFile) {
  hoidslam::testing::TempDir dir;
  FileDetector detector(WriteTwoFrames(dir));
  try {
    detector.Detect(kFirst + 1.0, cv::Mat());
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("detections.jsonl"));
    EXPECT_THAT(e.what(), HasSubstr("1341846314.592026"));
  }
}

TEST(FileDetector, ImageOfAnotherSizeThanTheHeaderSaysIsAnInputError) {
  hoidslam::testing::TempDir dir;
  FileDetector detector(WriteTwoFrames(dir));
  try {
    detector.Detect(kFirst, cv::Mat(240, 320, CV_8UC3));
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("640×480"));
    EXPECT_THAT(e.what(), HasSubstr("320×240"));
  }
}

TEST(FileDetector, CheckCoversCatchesAFileForAnotherSequenceUpFront) {
  hoidslam::testing::TempDir dir;
  const FileDetector detector(WriteTwoFrames(dir));
  EXPECT_NO_THROW(detector.CheckCovers({kFirst, kSecond}, "walking_xyz"));
  EXPECT_THROW(detector.CheckCovers({kFirst, kSecond, kSecond + 0.033}, "walking_xyz"), core::InputError);
  EXPECT_THROW(detector.CheckCovers({kFirst}, "sitting_static"), core::InputError);
}

TEST(FileDetector, HandWrittenFileWithoutHeaderIsNamedByItsFileName) {
  hoidslam::testing::TempDir dir;
  std::ofstream(dir / "mine.jsonl") << R"({"timestamp":1.5,"detections":[]})" << '\n';
  FileDetector detector(dir / "mine.jsonl");
  EXPECT_TRUE(detector.Detect(1.5, cv::Mat(10, 10, CV_8UC3)).empty());
  EXPECT_EQ(detector.Name(), "mine.jsonl");
}

TEST(FileDetector, MissingOrMalformedFileIsAnInputError) {
  hoidslam::testing::TempDir dir;
  EXPECT_THROW(FileDetector(dir / "absent.jsonl"), core::InputError);
  std::ofstream(dir / "bad.jsonl") << "{\"timestamp\":\n";
  EXPECT_THROW(FileDetector(dir / "bad.jsonl"), core::InputError);
}

}  // namespace
}  // namespace hoidslam::detect
