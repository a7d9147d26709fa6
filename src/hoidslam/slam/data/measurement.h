#pragma once
// What an optimiser knows about one keypoint, and the RGB-D camera it was seen with. ORB-SLAM's RGB-D
// convention: a keypoint with valid depth z also has a virtual right-image coordinate ur = u - bf / z, so a depth
// measurement is a third pixel residual with the same noise model as u and v.

#include <Eigen/Core>

#include "hoidslam/core/camera.h"

namespace hoidslam::slam {

// The pinhole model of undistorted keypoints plus the virtual stereo baseline of depth measurements.
struct RgbdCamera {
  double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;
  double bf = 40.0;  // baseline (metres) times fx (pixels)

  static RgbdCamera From(const core::CameraIntrinsics& intrinsics, double bf) {
    return {intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy, bf};
  }
  Eigen::Vector2d Project(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
  // The virtual right coordinate of a point in camera coordinates.
  double ProjectRight(const Eigen::Vector3d& p_c) const { return Project(p_c).x() - bf / p_c.z(); }
};

// One keypoint observation: undistorted pixel (u, v); for a keypoint with valid depth the virtual right
// coordinate ur (>= 0 is not required: ur is only meaningful when has_depth); inv_sigma2 = 1 / scale[level]^2.
// disparity_information > 0 has bundle adjustment weigh the depth as the disparity u − ur alone, with this
// information (1 / σ², from core::DepthNoiseModel), instead of as the pixel ur.
struct KeypointMeasurement {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double ur = 0.0;
  bool has_depth = false;
  double inv_sigma2 = 1.0;
  double disparity_information = 0.0;
};

// χ² thresholds at 95 % (ORB-SLAM's): 2 degrees of freedom for (u, v), 3 for (u, v, ur).
inline constexpr double kChi2Mono = 5.991;
inline constexpr double kChi2Stereo = 7.815;

}  // namespace hoidslam::slam
