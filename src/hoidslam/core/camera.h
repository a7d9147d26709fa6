#pragma once
// The pinhole RGB-D camera model (with the radial-tangential distortion of OpenCV / ORB-SLAM3 settings).

#include <Eigen/Core>

namespace hoidslam::core {

struct CameraIntrinsics {
  double fx = 535.4, fy = 539.2;  // focal lengths, pixels (defaults: TUM fr3)
  double cx = 320.1, cy = 247.6;  // principal point, pixels
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;  // distortion (OpenCV order)
  int width = 640, height = 480;  // image size, pixels

  bool operator==(const CameraIntrinsics&) const = default;

  bool HasDistortion() const { return k1 != 0.0 || k2 != 0.0 || p1 != 0.0 || p2 != 0.0 || k3 != 0.0; }

  // Pixel of a point in camera coordinates (z forward), ignoring distortion.
  Eigen::Vector2d Project(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
  // Point in camera coordinates at pixel (u, v) and depth z (metres), ignoring distortion.
  Eigen::Vector3d Unproject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
};

}  // namespace hoidslam::core
