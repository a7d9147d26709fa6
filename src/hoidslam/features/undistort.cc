#include "hoidslam/features/undistort.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace hoidslam::features {

std::vector<cv::Point2f> UndistortKeypoints(std::span<const cv::KeyPoint> keypoints,
                                            const core::CameraIntrinsics& camera) {
  std::vector<cv::Point2f> points;
  points.reserve(keypoints.size());
  for (const cv::KeyPoint& kp : keypoints) points.push_back(kp.pt);
  if (points.empty() || !camera.HasDistortion()) return points;

  const cv::Matx33d k(camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0);
  const cv::Matx<double, 1, 5> distortion(camera.k1, camera.k2, camera.p1, camera.p2, camera.k3);
  // P = K maps the undistorted normalised coordinates back to pixels.
  std::vector<cv::Point2f> undistorted;
  cv::undistortPoints(points, undistorted, k, distortion, cv::noArray(), k);
  return undistorted;
}

}  // namespace hoidslam::features
