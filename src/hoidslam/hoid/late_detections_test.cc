#include "hoidslam/hoid/late_detections.h"

#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "hoidslam/core/error.h"

namespace hoidslam::hoid {
namespace {

const cv::Size kImage(640, 480);

core::Detection Person(float x, float y) {
  return core::Detection{.class_id = 0, .label = "person", .score = 0.9F, .box = cv::Rect2f(x, y, 100, 200)};
}

// Keypoints on a person at (100, 100) and their descriptors; `shift` moves them.
struct PersonKeypoints {
  cv::Mat descriptors = cv::Mat(30, 32, CV_8UC1);
  PersonKeypoints() { cv::RNG(7).fill(descriptors, cv::RNG::UNIFORM, 0, 256); }
  std::vector<cv::KeyPoint> At(cv::Point2f shift) const {
    std::vector<cv::KeyPoint> keypoints;
    for (int i = 0; i < 30; ++i) keypoints.emplace_back(cv::Point2f(110.0F + 2.5F * i, 110.0F + 6.0F * i) + shift, 31.0F);
    return keypoints;
  }
};

TEST(LateDetections, DetectionsOfTheFrameItselfStayAsTheyAre) {
  LateDetections late(kImage);
  const PersonKeypoints person;
  late.Remember(0, person.At({0, 0}), person.descriptors);
  const std::vector<CarriedDetection> carried = late.Carry(0, std::vector{Person(100, 100)}, 0);
  ASSERT_EQ(carried.size(), 1U);
  EXPECT_EQ(carried[0].carry, Carry::kNone);
  EXPECT_EQ(carried[0].detection.box, cv::Rect2f(100, 100, 100, 200));
}

TEST(LateDetections, KeypointsFartherThanTheMotionBoundAreNoMatch) {
  LateDetections late(kImage);  // within 30 px + 15 px a frame of age
  const PersonKeypoints person;
  late.Remember(0, person.At({0, 0}), person.descriptors);
  late.Remember(1, person.At({50, 0}), person.descriptors);
  EXPECT_EQ(late.Carry(0, std::vector{Person(100, 100)}, 1)[0].carry, Carry::kGrown);
  late.Remember(2, person.At({50, 0}), person.descriptors);
  EXPECT_EQ(late.Carry(0, std::vector{Person(100, 100)}, 2)[0].carry, Carry::kKeypoints);
}

TEST(LateDetections, ALateBoxFollowsItsKeypointsToTheFrameBeingTracked) {
  LateDetections late(kImage);
  const PersonKeypoints person;
  for (int frame = 0; frame <= 3; ++frame) {
    late.Remember(static_cast<std::size_t>(frame), person.At({8.0F * frame, 2.0F * frame}), person.descriptors);
  }
  const std::vector<CarriedDetection> carried = late.Carry(0, std::vector{Person(100, 100)}, 3);
  ASSERT_EQ(carried.size(), 1U);
  EXPECT_EQ(carried[0].carry, Carry::kKeypoints);
  EXPECT_EQ(carried[0].detection.box, cv::Rect2f(124, 106, 100, 200));
  EXPECT_EQ(carried[0].detection.label, "person");
  EXPECT_EQ(late.frames(), 4U);
}

TEST(LateDetections, ABoxWithoutKeypointsGrowsWithItsAgeUpToTheLimit) {
  LateDetectionOptions options;
  options.grow_per_frame = 0.05;
  options.max_grow = 0.2;
  LateDetections late(kImage, options);
  for (std::size_t frame = 0; frame <= 10; ++frame) late.Remember(frame, {}, cv::Mat());
  const std::vector<CarriedDetection> two = late.Carry(0, std::vector{Person(200, 100)}, 2);
  ASSERT_EQ(two.size(), 1U);
  EXPECT_EQ(two[0].carry, Carry::kGrown);
  EXPECT_FLOAT_EQ(two[0].detection.box.x, 190.0F);  // 10 % of 100 px on each side
  EXPECT_FLOAT_EQ(two[0].detection.box.height, 240.0F);
  const std::vector<CarriedDetection> ten = late.Carry(0, std::vector{Person(200, 100)}, 10);
  EXPECT_FLOAT_EQ(ten[0].detection.box.width, 140.0F);  // capped at 20 %
}

TEST(LateDetections, BoxesAreClippedToTheImageAndThoseCarriedOutOfItLeftOut) {
  LateDetections late(kImage);
  const PersonKeypoints person;
  // A person at the left edge, whose keypoints move 115 px left in six frames: out of the image.
  late.Remember(0, person.At({-90, 0}), person.descriptors);
  for (std::size_t frame = 1; frame < 6; ++frame) late.Remember(frame, {}, cv::Mat());
  late.Remember(6, person.At({-205, 0}), person.descriptors);
  const std::vector<CarriedDetection> carried = late.Carry(0, std::vector{Person(10, 100), Person(600, 400)}, 6);
  ASSERT_EQ(carried.size(), 1U);  // the one who walked out of the image is left out; the other box is clipped
  // Grown by 6 × 4 % a side (no keypoints on it), then clipped to 640 × 480.
  EXPECT_EQ(carried[0].detection.box, cv::Rect2f(576, 352, 64, 128));
}

TEST(LateDetections, FramesBeforeTheNewestDetectionsAreLetGo) {
  LateDetectionOptions options;
  options.max_frames = 5;
  LateDetections late(kImage, options);
  for (std::size_t frame = 0; frame < 8; ++frame) late.Remember(frame, {}, cv::Mat());
  EXPECT_EQ(late.frames(), 5U);  // at most max_frames
  late.Carry(6, {}, 7);
  EXPECT_EQ(late.frames(), 2U);  // detections come in frame order: nothing before frame 6 is needed again
}

TEST(LateDetectionOptions, CheckNamesTheOption) {
  LateDetectionOptions options;
  options.grow_per_frame = -0.1;
  EXPECT_THROW(LateDetections(kImage, options), core::InputError);
  options = {};
  options.max_frames = 0;
  EXPECT_THROW(options.Check(), core::InputError);
}

}  // namespace
}  // namespace hoidslam::hoid
