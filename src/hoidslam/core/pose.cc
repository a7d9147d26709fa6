#include "hoidslam/core/pose.h"

#include <numbers>

namespace hoidslam::core {

Pose PoseFromTranslationQuaternion(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  Pose pose = Pose::Identity();
  pose.linear() = q.normalized().toRotationMatrix();
  pose.translation() = t;
  return pose;
}

double RotationAngleDegrees(const Eigen::Matrix3d& rotation) {
  // The angle arccos((trace R - 1) / 2), computed through a quaternion so that small angles keep their digits.
  return Eigen::AngleAxisd(rotation).angle() * 180.0 / std::numbers::pi;
}

}  // namespace hoidslam::core
