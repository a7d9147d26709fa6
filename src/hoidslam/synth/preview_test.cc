#include "hoidslam/synth/preview.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/sequence_writer.h"
#include "hoidslam/synth/test_scenarios.h"
#include "support/temp_dir.h"

namespace hoidslam::synth {
namespace {

TEST(Preview, TilesTheChosenFramesSideBySide) {
  testing::TempDir temp;
  SynthOptions options;
  options.out = temp / "seq";
  WriteSequence(fixtures::SmallScenario(fixtures::kWalkThenStop, 4), options);
  PreviewOptions preview;
  preview.frames = {0, 3};
  preview.scale = 0.25;
  const cv::Mat image = SequencePreview(temp / "seq", preview);
  // Each tile: 2 x 2 images of 160 x 120 plus a 2-pixel frame.
  EXPECT_EQ(image.size(), cv::Size(2 * (2 * 160 + 4), 2 * 120 + 4));
  EXPECT_EQ(image.type(), CV_8UC3);
  // The moving walker is painted red in the mask quarter of the first tile.
  const cv::Mat mask_quarter = image(cv::Rect(2 + 160, 2 + 120, 160, 120));
  cv::Mat red;
  cv::inRange(mask_quarter, cv::Scalar(0, 0, 200), cv::Scalar(80, 80, 255), red);
  EXPECT_GT(cv::countNonZero(red), 100);

  WritePreviewPng(temp / "preview.png", image);
  EXPECT_EQ(cv::imread((temp / "preview.png").string()).size(), image.size());
}

TEST(Preview, AFrameBeyondTheSequenceNamesTheParameter) {
  testing::TempDir temp;
  SynthOptions options;
  options.out = temp / "seq";
  WriteSequence(fixtures::SmallScenario("[]", 2), options);
  PreviewOptions preview;
  preview.frames = {5};
  try {
    SequencePreview(temp / "seq", preview);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("preview.frames: frame 5 is beyond the 2 frames"));
  }
  EXPECT_THROW(SequencePreview(temp / "missing", {}), core::InputError);
}

}  // namespace
}  // namespace hoidslam::synth
