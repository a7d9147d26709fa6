#include "hoidslam/hoid/keypoint_motion.h"

#include <numeric>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

namespace hoidslam::hoid {
namespace {

// 40 keypoints on a diagonal with distinct random descriptors.
struct Cloud {
  std::vector<cv::Point2f> points;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors = cv::Mat(40, 32, CV_8UC1);

  Cloud() {
    cv::RNG rng(5);
    rng.fill(descriptors, cv::RNG::UNIFORM, 0, 256);
    for (int i = 0; i < 40; ++i) points.emplace_back(120.0F + 4.0F * i, 100.0F + 7.0F * i);
  }
  std::vector<cv::KeyPoint> Moved(cv::Point2f by) const {
    std::vector<cv::KeyPoint> out;
    for (const cv::Point2f& p : points) out.emplace_back(p + by, 31.0F);
    return out;
  }
  std::vector<std::size_t> All() const {
    std::vector<std::size_t> all(points.size());
    std::iota(all.begin(), all.end(), 0);
    return all;
  }
};

const cv::Rect2f kEverywhere(0, 0, 640, 480);

TEST(MedianKeypointMotion, FindsHowTheKeypointsMoved) {
  const Cloud cloud;
  const auto motion = MedianKeypointMotion(cloud.points, cloud.descriptors, cloud.All(),
                                           cloud.Moved({15.0F, -6.0F}), cloud.descriptors, kEverywhere);
  ASSERT_TRUE(motion);
  EXPECT_FLOAT_EQ(motion->x, 15.0F);
  EXPECT_FLOAT_EQ(motion->y, -6.0F);
}

TEST(MedianKeypointMotion, OutvotesAFewWrongMatches) {
  const Cloud cloud;
  std::vector<cv::KeyPoint> moved = cloud.Moved({3.0F, 2.0F});
  for (int i = 0; i < 10; ++i) moved[static_cast<std::size_t>(i)].pt += cv::Point2f(200.0F, 0.0F);
  const auto motion =
      MedianKeypointMotion(cloud.points, cloud.descriptors, cloud.All(), moved, cloud.descriptors, kEverywhere);
  ASSERT_TRUE(motion);
  EXPECT_FLOAT_EQ(motion->x, 3.0F);
}

TEST(MedianKeypointMotion, NeedsFiveMatchesInsideTheWindow) {
  const Cloud cloud;
  const std::vector<cv::KeyPoint> moved = cloud.Moved({0.0F, 0.0F});
  const std::vector<std::size_t> four = {0, 1, 2, 3};
  EXPECT_FALSE(MedianKeypointMotion(cloud.points, cloud.descriptors, four, moved, cloud.descriptors, kEverywhere));
  // Only the first three keypoints lie in this window.
  EXPECT_FALSE(MedianKeypointMotion(cloud.points, cloud.descriptors, cloud.All(), moved, cloud.descriptors,
                                    cv::Rect2f(110, 90, 20, 30)));
}

TEST(MedianKeypointMotion, UnrelatedDescriptorsGiveNoMotion) {
  const Cloud cloud;
  cv::Mat other(40, 32, CV_8UC1);
  cv::RNG(99).fill(other, cv::RNG::UNIFORM, 0, 256);
  EXPECT_FALSE(
      MedianKeypointMotion(cloud.points, cloud.descriptors, cloud.All(), cloud.Moved({1, 1}), other, kEverywhere));
  EXPECT_FALSE(
      MedianKeypointMotion(cloud.points, cloud.descriptors, cloud.All(), cloud.Moved({1, 1}), cv::Mat(), kEverywhere));
}

TEST(MedianKeypointMotion, DescriptorsOtherThanOrbsGiveNoMotion) {
  const Cloud cloud;
  const cv::Mat half = cloud.descriptors.colRange(0, 16).clone();
  EXPECT_FALSE(MedianKeypointMotion(cloud.points, half, cloud.All(), cloud.Moved({1, 1}), half, kEverywhere));
}

}  // namespace
}  // namespace hoidslam::hoid
