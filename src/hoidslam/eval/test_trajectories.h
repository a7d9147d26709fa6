#pragma once
// Trajectories with known properties for the eval tests (test-only, header-only).

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "hoidslam/core/pose.h"

namespace hoidslam::eval::test_data {

// A smooth camera path that moves along all three axes and turns about all three: `count` poses at `rate` Hz
// from `start` seconds.
inline core::Trajectory MakeLissajousTrajectory(std::size_t count, double rate, double start = 0.0) {
  core::Trajectory trajectory;
  for (std::size_t k = 0; k < count; ++k) {
    const double t = static_cast<double>(k) / rate;
    const Eigen::Vector3d position(1.5 * std::sin(0.7 * t), 0.8 * std::sin(1.1 * t + 0.3), 0.4 * std::cos(0.5 * t));
    const Eigen::Quaterniond q = Eigen::AngleAxisd(0.6 * std::sin(0.4 * t), Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(0.3 * std::cos(0.9 * t), Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(0.2 * t, Eigen::Vector3d::UnitX());
    trajectory.push_back({start + t, core::PoseFromTranslationQuaternion(position, q)});
  }
  return trajectory;
}

inline core::Pose RandomPose(std::mt19937& rng, double translation_scale = 5.0) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  const Eigen::Vector3d t(normal(rng), normal(rng), normal(rng));
  return core::PoseFromTranslationQuaternion(translation_scale * t, q);
}

// Every pose moved by T: T * T_wc (the same path seen from another world frame).
inline core::Trajectory Transformed(core::Trajectory trajectory, const core::Pose& T) {
  for (core::StampedPose& pose : trajectory) pose.T_wc = T * pose.T_wc;
  return trajectory;
}

}  // namespace hoidslam::eval::test_data
