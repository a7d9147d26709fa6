#include "hoidslam/features/undistort.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "support/geometry.h"

namespace hoidslam::features {
namespace {

// The Bonn RGB-D Dynamic camera, as in config/Bonn.yaml.
// Pixels over the whole 640×480 image, corners included.
std::vector<cv::Point2f> Grid() {
  std::vector<cv::Point2f> points;
  for (float y = 0.0F; y <= 480.0F; y += 40.0F) {
    for (float x = 0.0F; x <= 640.0F; x += 40.0F) points.emplace_back(x, y);
  }
  points.emplace_back(0.5F, 479.5F);
  points.emplace_back(639.5F, 0.5F);
  return points;
}

std::vector<cv::KeyPoint> KeypointsAt(const std::vector<cv::Point2f>& points) {
  std::vector<cv::KeyPoint> keypoints;
  for (const cv::Point2f& p : points) keypoints.emplace_back(p, 31.0F, 45.0F, 20.0F, 2);
  return keypoints;
}

TEST(UndistortKeypoints, WithoutDistortionReturnsThePositions) {
  const core::CameraIntrinsics camera;  // TUM fr3 defaults: no distortion
  ASSERT_FALSE(camera.HasDistortion());
  const std::vector<cv::Point2f> points = Grid();
  EXPECT_EQ(UndistortKeypoints(KeypointsAt(points), camera), points);
  EXPECT_TRUE(UndistortKeypoints({}, camera).empty());
  EXPECT_TRUE(UndistortKeypoints({}, testing::BonnIntrinsics()).empty());
}

TEST(UndistortKeypoints, InvertsTheBonnDistortion) {
  const core::CameraIntrinsics camera = testing::BonnIntrinsics();
  const cv::Matx33d k(camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0);
  const std::vector<double> distortion = {camera.k1, camera.k2, camera.p1, camera.p2, camera.k3};

  // Ideal pixels -> rays -> distorted pixels through OpenCV's forward model -> back.
  const std::vector<cv::Point2f> ideal = Grid();
  std::vector<cv::Point3f> rays;
  for (const cv::Point2f& p : ideal) {
    rays.emplace_back(static_cast<float>((p.x - camera.cx) / camera.fx),
                      static_cast<float>((p.y - camera.cy) / camera.fy), 1.0F);
  }
  std::vector<cv::Point2f> distorted;
  cv::projectPoints(rays, cv::Vec3d::zeros(), cv::Vec3d::zeros(), k, distortion, distorted);

  const std::vector<cv::Point2f> undistorted = UndistortKeypoints(KeypointsAt(distorted), camera);
  ASSERT_EQ(undistorted.size(), ideal.size());
  double largest_shift = 0.0;
  for (std::size_t i = 0; i < ideal.size(); ++i) {
    EXPECT_NEAR(undistorted[i].x, ideal[i].x, 0.01) << i;
    EXPECT_NEAR(undistorted[i].y, ideal[i].y, 0.01) << i;
    largest_shift =
        std::max(largest_shift, std::hypot(double{distorted[i].x} - ideal[i].x, double{distorted[i].y} - ideal[i].y));
  }
  // The distortion is real at the corners, so the test means something.
  EXPECT_GT(largest_shift, 1.0);
}

}  // namespace
}  // namespace hoidslam::features
