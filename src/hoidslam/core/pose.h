#pragma once
// Rigid poses. Convention (DESIGN.md): poses are camera-to-world (T_wc) unless a name says otherwise;
// T_ab maps points from frame b to frame a.

#include <vector>

#include <Eigen/Geometry>

namespace hoidslam::core {

using Pose = Eigen::Isometry3d;

// A pose at a time, as in a TUM trajectory line `timestamp tx ty tz qx qy qz qw`.
struct StampedPose {
  double timestamp = 0.0;  // seconds
  Pose T_wc = Pose::Identity();
};

using Trajectory = std::vector<StampedPose>;

// Builds a pose from a translation and a (not necessarily normalised) quaternion.
Pose PoseFromTranslationQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q);

// The angle of a rotation, in degrees (in [0, 180]).
double RotationAngleDegrees(const Eigen::Matrix3d& rotation);

}  // namespace hoidslam::core
