#pragma once
// Poses and cameras that geometry tests build again and again.

#include <Eigen/Geometry>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"

namespace hoidslam::testing {

// The pose rotating by |axis_angle| radians about axis_angle's direction, then translating by t.
inline core::Pose PoseFromAxisAngle(const Eigen::Vector3d& axis_angle, const Eigen::Vector3d& t) {
  core::Pose pose = core::Pose::Identity();
  const double angle = axis_angle.norm();
  if (angle > 0.0) pose.linear() = Eigen::AngleAxisd(angle, axis_angle / angle).toRotationMatrix();
  pose.translation() = t;
  return pose;
}

// The Bonn RGB-D Dynamic camera of config/Bonn.yaml: a lens with radial and tangential distortion.
inline core::CameraIntrinsics BonnIntrinsics() {
  core::CameraIntrinsics c;
  c.fx = 542.822841;
  c.fy = 542.576870;
  c.cx = 315.593520;
  c.cy = 237.756098;
  c.k1 = 0.039903;
  c.k2 = -0.099343;
  c.p1 = -0.000730;
  c.p2 = -0.000144;
  c.k3 = 0.0;
  return c;
}

}  // namespace hoidslam::testing
