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

// Standard deviation (metres) of a Kinect-class depth measurement at depth z (metres), after Nguyen, Izadi & Lovell
// (2012): 0.0012 + 0.0019 (z − 0.4)².
inline double KinectDepthSigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }

// How far the final map adjustment trusts a depth measurement: σ(z) = factor × KinectDepthSigma(z), the factor
// covering what the model leaves out (depth and colour registered imperfectly, keypoints on depth edges, sensors
// noisier than a Kinect). Elsewhere depth is weighed as ORB-SLAM3 weighs it, as one pixel of the virtual right
// coordinate (some 10 cm at 2 m with a 40 px·m baseline).
struct DepthNoiseModel {
  double factor = 2.0;  // > 0

  double Sigma(double z) const { return factor * KinectDepthSigma(z); }
  // 1 / σ² of the disparity bf / z measured at depth z: σ_d = bf σ(z) / z².
  double DisparityInformation(double bf, double z) const {
    const double sigma_d = bf * Sigma(z) / (z * z);
    return 1.0 / (sigma_d * sigma_d);
  }
};

}  // namespace hoidslam::core
