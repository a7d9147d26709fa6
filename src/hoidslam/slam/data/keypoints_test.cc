#include "hoidslam/slam/data/keypoints.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "hoidslam/slam/data/sensor.h"
#include "support/geometry.h"

namespace hoidslam::slam {
namespace {

constexpr double kBf = 40.0;

std::shared_ptr<const Sensor> MakeSensor(const core::CameraIntrinsics& intrinsics = {}) {
  return Sensor::Make(intrinsics, kBf, 3.0, features::ScalePyramid::Make(8, 1.2));
}

// The Bonn camera (config/Bonn.yaml), with its lens distortion.
cv::KeyPoint Kp(float x, float y, int level = 0, float angle = 0.0F) { return {x, y, 31.0F, angle, 1.0F, level}; }

// Descriptor i: every byte equal to i, so rows are told apart.
cv::Mat Descriptors(std::size_t n) {
  cv::Mat d(static_cast<int>(n), 32, CV_8UC1);
  for (int i = 0; i < d.rows; ++i) d.row(i).setTo(static_cast<std::uint8_t>(i));
  return d;
}

KeypointSet MakeSet(const std::shared_ptr<const Sensor>& sensor, const std::vector<cv::KeyPoint>& keypoints,
                    const cv::Mat& depth = {}, const cv::Mat& bgr = {}) {
  return KeypointSet(sensor, keypoints, Descriptors(keypoints.size()), depth, bgr);
}

cv::Mat EmptyDepth() { return cv::Mat::zeros(480, 640, CV_32FC1); }

TEST(KeypointSet, SamplesDepthAndRightCoordinateAtRoundedKeypoint) {
  const auto sensor = MakeSensor();
  cv::Mat depth = EmptyDepth();
  depth.at<float>(100, 200) = 2.0F;
  depth.at<float>(100, 201) = 4.0F;  // the neighbour a keypoint at x = 200.6 rounds to
  depth.at<float>(50, 50) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(60, 60) = -1.0F;
  depth.at<float>(70, 70) = std::numeric_limits<float>::infinity();
  cv::Mat bgr(480, 640, CV_8UC3, cv::Scalar(1, 2, 3));
  bgr.at<cv::Vec3b>(100, 200) = cv::Vec3b(10, 20, 30);

  const KeypointSet set = MakeSet(sensor,
                                  {Kp(200.3F, 99.8F), Kp(200.6F, 100.2F), Kp(300, 300), Kp(50, 50), Kp(60, 60),
                                   Kp(70, 70), Kp(-3, 10), Kp(639.4F, 479.4F)},
                                  depth, bgr);
  ASSERT_EQ(set.size(), 8);
  EXPECT_TRUE(set.has_depth(0));
  EXPECT_FLOAT_EQ(set.depth(0), 2.0F);
  EXPECT_NEAR(set.right(0), 200.3 - kBf / 2.0, 1e-4);
  EXPECT_TRUE(set.has_depth(1));
  EXPECT_FLOAT_EQ(set.depth(1), 4.0F);
  EXPECT_NEAR(set.right(1), 200.6 - kBf / 4.0, 1e-4);
  // Zero, NaN, negative and infinite depth, and a keypoint off the image: no depth.
  for (int i = 2; i <= 7; ++i) {
    EXPECT_FALSE(set.has_depth(i)) << i;
    EXPECT_EQ(set.depth(i), 0.0F) << i;
  }
  EXPECT_EQ(set.num_with_depth(), 2);
  EXPECT_EQ(set.color(0), cv::Vec3b(10, 20, 30));
  EXPECT_EQ(set.color(2), cv::Vec3b(1, 2, 3));
  EXPECT_EQ(set.color(6), cv::Vec3b(0, 0, 0));  // off the image

  // Unprojecting gives back a point that projects onto the keypoint at the sampled depth.
  const Eigen::Vector3d p = set.Unproject(0);
  EXPECT_DOUBLE_EQ(p.z(), 2.0);
  const Eigen::Vector2d uv = sensor->camera.Project(p);
  EXPECT_NEAR(uv.x(), 200.3, 1e-4);
  EXPECT_NEAR(uv.y(), 99.8, 1e-4);
  EXPECT_NEAR(sensor->camera.ProjectRight(p), set.right(0), 1e-4);
}

TEST(KeypointSet, WithoutDepthImageNothingHasDepth) {
  const KeypointSet set = MakeSet(MakeSensor(), {Kp(10, 10), Kp(20, 20)});
  EXPECT_EQ(set.num_with_depth(), 0);
  EXPECT_FALSE(set.has_depth(0));
  EXPECT_FALSE(set.Measurement(1).has_depth);
}

TEST(KeypointSet, MeasurementCarriesLevelWeight) {
  const auto sensor = MakeSensor();
  cv::Mat depth = EmptyDepth();
  depth.at<float>(10, 30) = 1.5F;
  std::vector<cv::KeyPoint> keypoints;
  for (int l = 0; l < 8; ++l) keypoints.push_back(Kp(static_cast<float>(30 + 40 * l), 10.0F, l));
  const KeypointSet set = MakeSet(sensor, keypoints, depth);
  for (int l = 0; l < 8; ++l) {
    const KeypointMeasurement m = set.Measurement(l);
    EXPECT_NEAR(m.inv_sigma2, std::pow(1.2, -2.0 * l), 1e-6) << l;
    EXPECT_DOUBLE_EQ(m.uv.x(), 30.0 + 40.0 * l);
    EXPECT_DOUBLE_EQ(m.uv.y(), 10.0);
    EXPECT_EQ(m.has_depth, l == 0);
  }
  EXPECT_NEAR(set.Measurement(0).ur, 30.0 - kBf / 1.5, 1e-4);
}

TEST(KeypointSet, ConstructorRejectsBadInput) {
  const auto sensor = MakeSensor();
  const std::vector<cv::KeyPoint> kps = {Kp(1, 1), Kp(2, 2), Kp(3, 3)};
  EXPECT_THROW(KeypointSet(sensor, kps, Descriptors(2), cv::Mat(), cv::Mat()), std::invalid_argument);
  EXPECT_THROW(KeypointSet(sensor, kps, Descriptors(4), cv::Mat(), cv::Mat()), std::invalid_argument);
  EXPECT_THROW(KeypointSet(sensor, kps, cv::Mat::zeros(3, 16, CV_8UC1), cv::Mat(), cv::Mat()), std::invalid_argument);
  // Raw 16-bit TUM depth must be converted to metres first.
  EXPECT_THROW(KeypointSet(sensor, kps, Descriptors(3), cv::Mat::zeros(480, 640, CV_16UC1), cv::Mat()),
               std::invalid_argument);
  EXPECT_THROW(KeypointSet(sensor, kps, Descriptors(3), cv::Mat::zeros(480, 640, CV_64FC1), cv::Mat()),
               std::invalid_argument);
  EXPECT_THROW(KeypointSet(sensor, kps, Descriptors(3), EmptyDepth(), cv::Mat::zeros(480, 640, CV_8UC1)),
               std::invalid_argument);
  EXPECT_NO_THROW(KeypointSet(sensor, kps, Descriptors(3), EmptyDepth(), cv::Mat::zeros(480, 640, CV_8UC3)));
  EXPECT_NO_THROW(KeypointSet(sensor, {}, cv::Mat(), EmptyDepth(), cv::Mat()));
  // Stored per-keypoint samples: one depth and one colour each.
  const std::vector<cv::Vec3b> colors(3);
  EXPECT_THROW(KeypointSet(sensor, kps, Descriptors(3), std::vector<float>(2), colors), std::invalid_argument);
  EXPECT_THROW(KeypointSet(sensor, kps, Descriptors(3), std::vector<float>(3), std::vector<cv::Vec3b>(4)),
               std::invalid_argument);
}

TEST(KeypointSet, StoredSamplesGiveTheSetTheImagesGave) {
  const auto sensor = MakeSensor();
  const std::vector<cv::KeyPoint> kps = {Kp(10, 10), Kp(20, 10), Kp(30, 10)};
  cv::Mat depth = EmptyDepth();
  depth.at<float>(10, 10) = 1.5F;
  const KeypointSet sampled(sensor, kps, Descriptors(3), depth, cv::Mat());
  // A depth that is not a number or not positive is none, as in a depth image.
  const KeypointSet stored(sensor, kps, Descriptors(3), {1.5F, std::nanf(""), -1.0F}, std::vector<cv::Vec3b>(3));
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(stored.depth(i), sampled.depth(i));
    EXPECT_EQ(stored.right(i), sampled.right(i));
  }
  EXPECT_EQ(stored.num_with_depth(), 1);
  EXPECT_EQ(stored.FeaturesInArea(20, 10, 15), sampled.FeaturesInArea(20, 10, 15));
}

std::vector<int> BruteForce(const KeypointSet& set, double u, double v, double r, int min_level, int max_level) {
  std::vector<int> found;
  for (int i = 0; i < set.size(); ++i) {
    const int l = set.level(i);
    if (l < min_level || (max_level >= 0 && l > max_level)) continue;
    if (std::abs(set.undistorted(i).x() - u) < r && std::abs(set.undistorted(i).y() - v) < r) found.push_back(i);
  }
  return found;
}

// The grid must be an exact accelerator: same indices, same order as scanning every keypoint.
void ExpectGridMatchesBruteForce(const std::shared_ptr<const Sensor>& sensor, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> x(0.0F, 640.0F), y(0.0F, 480.0F);
  std::uniform_int_distribution<int> level(0, 7);
  std::vector<cv::KeyPoint> kps;
  for (int i = 0; i < 1500; ++i) kps.push_back(Kp(x(rng), y(rng), level(rng)));
  // The image border and corners, where the grid's first and last cells are.
  for (const auto& [bx, by] : {std::pair{0.0F, 0.0F}, {639.99F, 0.0F}, {0.0F, 479.99F}, {639.99F, 479.99F},
                               {320.0F, 0.0F}, {0.0F, 240.0F}, {639.99F, 240.0F}, {320.0F, 479.99F}}) {
    kps.push_back(Kp(bx, by, level(rng)));
  }
  // Duplicates at one position.
  for (int l = 0; l < 8; ++l) kps.push_back(Kp(123.4F, 321.0F, l));
  const KeypointSet set = MakeSet(sensor, kps);

  std::uniform_real_distribution<double> cu(-50.0, 690.0), cv_(-50.0, 530.0);
  const std::vector<std::pair<int, int>> levels = {{0, -1}, {0, 0}, {2, 4}, {3, 3}, {5, -1}, {7, 7}, {1, 6}};
  int total = 0;
  for (const double r : {0.3, 1.0, 2.5, 7.0, 10.0, 19.9, 40.0, 100.0, 400.0, 800.0}) {
    for (int k = 0; k < 60; ++k) {
      const double u = k == 0 ? 123.4 : cu(rng);
      const double v = k == 0 ? 321.0 : cv_(rng);
      for (const auto& [lo, hi] : levels) {
        const std::vector<int> expected = BruteForce(set, u, v, r, lo, hi);
        ASSERT_EQ(set.FeaturesInArea(u, v, r, lo, hi), expected) << "u " << u << " v " << v << " r " << r << " levels "
                                                                 << lo << ".." << hi;
        total += static_cast<int>(expected.size());
      }
    }
  }
  EXPECT_GT(total, 10000);  // the comparison was not trivially between empty lists
}

TEST(KeypointSet, FeaturesInAreaEqualsBruteForce) { ExpectGridMatchesBruteForce(MakeSensor(), 7); }

TEST(KeypointSet, FeaturesInAreaEqualsBruteForceWithDistortion) {
  ExpectGridMatchesBruteForce(MakeSensor(testing::BonnIntrinsics()), 11);
}

TEST(KeypointSet, FeaturesInAreaFiltersLevels) {
  std::vector<cv::KeyPoint> kps;
  for (int l = 0; l < 8; ++l) kps.push_back(Kp(100.0F + static_cast<float>(l) * 0.1F, 100.0F, l));
  kps.push_back(Kp(110.0F, 100.0F, 3));  // outside a 5 px window
  const KeypointSet set = MakeSet(MakeSensor(), kps);
  EXPECT_EQ(set.FeaturesInArea(100, 100, 5), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(set.FeaturesInArea(100, 100, 5, 2, 4), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(set.FeaturesInArea(100, 100, 5, 5), (std::vector<int>{5, 6, 7}));
  EXPECT_EQ(set.FeaturesInArea(100, 100, 5, 0, 0), (std::vector<int>{0}));
  EXPECT_EQ(set.FeaturesInArea(100, 100, 5, 3, 3), (std::vector<int>{3}));
  EXPECT_EQ(set.FeaturesInArea(100, 100, 10.5, 3, 3), (std::vector<int>{3, 8}));
  EXPECT_TRUE(set.FeaturesInArea(100, 100, 5, 4, 2).empty());
  // Strict window: a keypoint exactly `radius` away is not inside.
  EXPECT_EQ(set.FeaturesInArea(105, 100, 5, 0, 0), (std::vector<int>{}));
  EXPECT_TRUE(set.FeaturesInArea(-100, -100, 50).empty());
  EXPECT_TRUE(set.FeaturesInArea(1000, 100, 50).empty());
}

TEST(Sensor, RejectsCameraWithoutSize) {
  core::CameraIntrinsics c;
  c.width = 0;
  EXPECT_THROW(MakeSensor(c), std::invalid_argument);
}

TEST(Sensor, UndistortedBoundsWithoutDistortionAreTheImage) {
  const auto s = MakeSensor();
  EXPECT_EQ(s->min_x, 0.0F);
  EXPECT_EQ(s->max_x, 640.0F);
  EXPECT_EQ(s->min_y, 0.0F);
  EXPECT_EQ(s->max_y, 480.0F);
  EXPECT_FLOAT_EQ(s->grid_cell_inv_width, 64.0F / 640.0F);
  EXPECT_FLOAT_EQ(s->grid_cell_inv_height, 48.0F / 480.0F);
  EXPECT_TRUE(s->InImage(0, 0));
  EXPECT_FALSE(s->InImage(640, 10));
  EXPECT_FALSE(s->InImage(-0.01, 10));
  EXPECT_DOUBLE_EQ(s->camera.bf, kBf);
  EXPECT_EQ(s->pyramid.levels(), 8);
}

TEST(Sensor, DistortedBoundsEncloseTheUndistortedBorder) {
  const core::CameraIntrinsics c = testing::BonnIntrinsics();
  const auto s = MakeSensor(c);
  // Bonn's lens pushes the corners slightly outwards when undistorted: the bounds leave [0, 640) × [0, 480), by a
  // few pixels, not more.
  EXPECT_LT(s->min_x, 0.0F);
  EXPECT_GT(s->max_x, 640.0F);
  EXPECT_LT(s->min_y, 0.0F);
  EXPECT_GT(s->max_y, 480.0F);
  EXPECT_GT(s->min_x, -10.0F);
  EXPECT_LT(s->max_x, 650.0F);
  EXPECT_GT(s->min_y, -10.0F);
  EXPECT_LT(s->max_y, 490.0F);
  EXPECT_FLOAT_EQ(s->grid_cell_inv_width, 64.0F / (s->max_x - s->min_x));
  EXPECT_FLOAT_EQ(s->grid_cell_inv_height, 48.0F / (s->max_y - s->min_y));

  // Every point of the image border, undistorted, lies within the bounds (so no keypoint falls off the grid).
  std::vector<cv::Point2f> border;
  for (float t = 0.0F; t <= 1.0F; t += 0.01F) {
    border.emplace_back(640.0F * t, 0.0F);
    border.emplace_back(640.0F * t, 480.0F);
    border.emplace_back(0.0F, 480.0F * t);
    border.emplace_back(640.0F, 480.0F * t);
  }
  const cv::Matx33d k(c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0);
  const cv::Matx<double, 1, 5> d(c.k1, c.k2, c.p1, c.p2, c.k3);
  std::vector<cv::Point2f> undistorted;
  cv::undistortPoints(border, undistorted, k, d, cv::noArray(), k);
  for (const cv::Point2f& p : undistorted) {
    EXPECT_GE(p.x, s->min_x - 1e-3F);
    EXPECT_LE(p.x, s->max_x + 1e-3F);
    EXPECT_GE(p.y, s->min_y - 1e-3F);
    EXPECT_LE(p.y, s->max_y + 1e-3F);
  }
}

TEST(KeypointSet, DistortedKeypointsAreUndistortedButSampleDepthWhereSeen) {
  const auto sensor = MakeSensor(testing::BonnIntrinsics());
  cv::Mat depth = EmptyDepth();
  depth.at<float>(5, 5) = 2.0F;
  const KeypointSet set = MakeSet(sensor, {Kp(5, 5), Kp(315.59F, 237.76F)}, depth);
  // Near the corner the lens moves the keypoint by more than a pixel; at the principal point it does not.
  EXPECT_GT((set.undistorted(0) - Eigen::Vector2d(5, 5)).norm(), 1.0);
  EXPECT_LT((set.undistorted(1) - Eigen::Vector2d(315.59, 237.76)).norm(), 0.01);
  EXPECT_EQ(set.keypoint(0).pt, cv::Point2f(5, 5));
  ASSERT_TRUE(set.has_depth(0));
  EXPECT_NEAR(set.right(0), set.undistorted(0).x() - kBf / 2.0, 1e-6);
  // The search works on undistorted positions.
  EXPECT_EQ(set.FeaturesInArea(set.undistorted(0).x(), set.undistorted(0).y(), 0.5), (std::vector<int>{0}));
}

}  // namespace
}  // namespace hoidslam::slam
