#include "hoidslam/dense/fusible_depth.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace hoidslam::dense {
namespace {

DenseOptions NoMargin() {
  DenseOptions options;
  options.mask_margin = 0;
  return options;
}

TEST(FusibleDepth, KeepsTrustedAndFarDepthAndDropsWhatIsTooNearOrMissing) {
  cv::Mat depth(20, 20, CV_32FC1, cv::Scalar(2.0F));
  depth.at<float>(5, 5) = 0.1F;                    // nearer than min_depth
  depth(cv::Rect(14, 14, 6, 6)).setTo(3.5F);       // beyond max_depth (3 m): kept for the occupancy map's rays
  depth.at<float>(10, 2) = std::nanf("");          // no measurement
  const cv::Mat fused = FusibleDepth(depth, cv::Mat(), NoMargin());
  EXPECT_EQ(fused.at<float>(5, 5), 0.0F);
  EXPECT_EQ(fused.at<float>(17, 17), 3.5F);
  EXPECT_EQ(fused.at<float>(14, 14), 0.0F);        // the far region's outline is a depth edge
  EXPECT_EQ(fused.at<float>(10, 2), 0.0F);
  EXPECT_EQ(fused.at<float>(0, 19), 2.0F);         // far from every gap
}

TEST(FusibleDepth, LeavesOutBothSidesOfADepthEdge) {
  // A person 1 m in front of a wall at 3 m, columns 10 and up: the pixels along the outline mix the two.
  cv::Mat depth(20, 20, CV_32FC1, cv::Scalar(2.9F));
  depth.colRange(10, 20).setTo(1.0F);
  const cv::Mat fused = FusibleDepth(depth, cv::Mat(), NoMargin());
  for (const int col : {9, 10}) EXPECT_EQ(fused.at<float>(10, col), 0.0F) << col;
  EXPECT_EQ(fused.at<float>(10, 8), 2.9F);
  EXPECT_EQ(fused.at<float>(10, 11), 1.0F);
}

TEST(FusibleDepth, LeavesOutTheDroppedRegionGrownByTheMargin) {
  const cv::Mat depth(40, 40, CV_32FC1, cv::Scalar(2.0F));
  cv::Mat dropped(40, 40, CV_8UC1, cv::Scalar(0));
  dropped(cv::Rect(10, 10, 5, 5)).setTo(255);
  DenseOptions options;
  options.mask_margin = 3;
  const cv::Mat fused = FusibleDepth(depth, dropped, options);
  EXPECT_EQ(fused.at<float>(12, 12), 0.0F);  // inside
  EXPECT_EQ(fused.at<float>(12, 7), 0.0F);   // 3 px left of the region
  EXPECT_EQ(fused.at<float>(12, 6), 2.0F);   // 4 px: kept
  EXPECT_EQ(fused.at<float>(17, 17), 0.0F);  // the corner grows as a square
  EXPECT_EQ(cv::countNonZero(fused == 0.0F), 11 * 11);
}

TEST(FusibleDepth, RefusesImagesOfAnotherTypeOrSize) {
  const cv::Mat depth(10, 10, CV_32FC1, cv::Scalar(1.0F));
  EXPECT_THROW(FusibleDepth(cv::Mat(10, 10, CV_16UC1), cv::Mat(), DenseOptions{}), std::invalid_argument);
  EXPECT_THROW(FusibleDepth(depth, cv::Mat(5, 5, CV_8UC1), DenseOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace hoidslam::dense
