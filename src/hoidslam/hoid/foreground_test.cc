#include "hoidslam/hoid/foreground.h"

#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace hoidslam::hoid {
namespace {

// A 640×480 depth image of a wall at `wall` metres.
cv::Mat Wall(float wall) { return cv::Mat(480, 640, CV_32FC1, cv::Scalar(wall)); }

cv::KeyPoint At(float x, float y) { return cv::KeyPoint(x, y, 31.0F); }

TEST(ForegroundDepth, APersonBeforeAWallIsTheForegroundAndTheWallLiesBehindTheCut) {
  cv::Mat depth = Wall(4.0F);
  depth(cv::Rect(250, 100, 100, 300)).setTo(2.0F);  // the person fills the middle of their box
  const std::optional<DepthCluster> fg = ForegroundDepth(depth, cv::Rect2f(200, 80, 200, 340), {});
  ASSERT_TRUE(fg);
  EXPECT_NEAR(fg->median, 2.0F, 0.01F);
  EXPECT_LE(fg->near, 2.0F);
  EXPECT_GE(fg->cut, 2.5F - 1e-4F);  // half a metre of reach behind the person's middle
  EXPECT_LT(fg->cut, 4.0F);          // the wall is kept
}

TEST(ForegroundDepth, APersonBehindADeskIsStillDroppedWithTheDeskInFrontOfThem) {
  cv::Mat depth = Wall(4.5F);
  depth(cv::Rect(250, 100, 100, 300)).setTo(2.8F);  // the person, in the box's middle
  depth(cv::Rect(200, 300, 200, 120)).setTo(1.6F);  // a desk in front of them fills the bottom of the box
  const std::optional<DepthCluster> fg = ForegroundDepth(depth, cv::Rect2f(200, 80, 200, 340), {});
  ASSERT_TRUE(fg);
  EXPECT_NEAR(fg->median, 2.8F, 0.01F);  // the box's centre shows the person
  EXPECT_LE(fg->near, 1.6F);             // and the desk in front is part of what is dropped
  EXPECT_GE(fg->cut, 3.3F - 1e-4F);
  EXPECT_LT(fg->cut, 4.5F);
}

TEST(ForegroundDepth, APersonCutOffAtTheBoxEdgeIsNotLeftBehindTheCut) {
  // The person is only at the box's left edge (the image border cut them off); a monitor fills the centre.
  cv::Mat depth = Wall(4.0F);
  depth(cv::Rect(0, 100, 70, 380)).setTo(1.2F);
  depth(cv::Rect(60, 150, 140, 120)).setTo(2.6F);
  const std::optional<DepthCluster> fg = ForegroundDepth(depth, cv::Rect2f(0, 80, 200, 400), {});
  ASSERT_TRUE(fg);
  EXPECT_LE(fg->near, 1.2F);
  EXPECT_GT(fg->cut, 1.7F);  // the person (nearest mode with a share) and the monitor (at the centre) both drop
}

TEST(ForegroundDepth, NeedsValidDepth) {
  const core::HoidPlusOptions options;
  EXPECT_FALSE(ForegroundDepth(cv::Mat(), cv::Rect2f(0, 0, 10, 10), options));
  EXPECT_FALSE(ForegroundDepth(Wall(0.0F), cv::Rect2f(0, 0, 100, 100), options));          // all holes
  EXPECT_FALSE(ForegroundDepth(Wall(2.0F), cv::Rect2f(700, 10, 100, 100), options));       // off the image
  EXPECT_FALSE(ForegroundDepth(Wall(2.0F), cv::Rect2f(10, 10, 0, 100), options));          // no area
  EXPECT_THROW(ForegroundDepth(cv::Mat(480, 640, CV_16UC1), cv::Rect2f(0, 0, 10, 10), options), std::invalid_argument);
}

TEST(MarkKeypointsBehindForeground, KeepsTheBackgroundAndDropsTheForegroundItsEdgeAndHoles) {
  cv::Mat depth = Wall(4.0F);
  depth(cv::Rect(250, 100, 100, 300)).setTo(2.0F);
  depth.at<float>(200, 380) = 0.0F;  // a sensor hole on the wall
  const std::vector<ExclusionRegion> regions = {{.box = cv::Rect2f(200, 80, 200, 340), .cut = 2.5F, .edge_margin = 3}};
  const std::vector<cv::KeyPoint> keypoints = {
      At(300, 200),  // on the person
      At(220, 200),  // on the wall behind, inside the box
      At(352, 200),  // on the wall, 2 px from the person's edge: within the edge margin
      At(356, 200),  // on the wall, 6 px from the edge
      At(380, 200),  // on the hole
      At(500, 200),  // outside the box
  };
  std::vector<std::uint8_t> keep;
  MarkKeypointsBehindForeground(keypoints, depth, regions, keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 1, 0, 1, 0, 1}));

  // Without depth, or without a foreground (cut +inf), the whole box drops.
  MarkKeypointsBehindForeground(keypoints, cv::Mat(), regions, keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 1}));
  const std::vector<ExclusionRegion> whole = {{.box = cv::Rect2f(200, 80, 200, 340)}};
  MarkKeypointsBehindForeground(keypoints, depth, whole, keep);
  EXPECT_EQ(keep, (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 1}));
}

TEST(PaintExclusionRegions, PaintsExactlyThePixelsWhoseKeypointsWouldDrop) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> depth_value(0.5F, 5.0F);
  cv::Mat depth(120, 160, CV_32FC1);
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) depth.at<float>(y, x) = (x * 7 + y * 13) % 17 == 0 ? 0.0F : depth_value(rng);
  }
  const std::vector<ExclusionRegion> regions = {
      {.box = cv::Rect2f(10.5F, 20.0F, 60.0F, 50.3F), .cut = 2.0F, .edge_margin = 2},
      {.box = cv::Rect2f(100.0F, -5.0F, 80.0F, 40.0F), .cut = 1.0F, .edge_margin = 0},
      {.box = cv::Rect2f(40.0F, 80.0F, 30.0F, 30.0F)}};
  const cv::Mat painted = PaintExclusionRegions(regions, depth, depth.size());
  std::vector<cv::KeyPoint> pixels;
  for (int y = 0; y < depth.rows; ++y) {
    for (int x = 0; x < depth.cols; ++x) pixels.push_back(At(static_cast<float>(x), static_cast<float>(y)));
  }
  std::vector<std::uint8_t> keep;
  MarkKeypointsBehindForeground(pixels, depth, regions, keep);
  int dropped = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const auto x = static_cast<int>(pixels[i].pt.x);
    const auto y = static_cast<int>(pixels[i].pt.y);
    ASSERT_EQ(painted.at<std::uint8_t>(y, x) != 0, keep[i] == 0) << x << "," << y;
    dropped += keep[i] == 0 ? 1 : 0;
  }
  EXPECT_GT(dropped, 1000);  // the test covers both verdicts
  EXPECT_LT(dropped, 10000);
}

TEST(GrowBox, GrowsEachSideByAShareOfTheSize) {
  const cv::Rect2f grown = GrowBox(cv::Rect2f(100, 50, 40, 200), 0.1);
  EXPECT_FLOAT_EQ(grown.x, 96.0F);
  EXPECT_FLOAT_EQ(grown.y, 30.0F);
  EXPECT_FLOAT_EQ(grown.width, 48.0F);
  EXPECT_FLOAT_EQ(grown.height, 240.0F);
}

}  // namespace
}  // namespace hoidslam::hoid
