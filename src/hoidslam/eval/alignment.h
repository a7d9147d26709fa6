#pragma once
// Closed-form alignment of one point set onto another (Horn / Umeyama through an SVD), as evaluate_ate.py
// aligns an estimated trajectory to the ground truth.

#include <Eigen/Core>

namespace hoidslam::eval {

// data ≈ scale * rotation * model + translation.
struct Alignment {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // a proper rotation (determinant +1)
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;  // 1 unless the scale was estimated

  Eigen::Vector3d Apply(const Eigen::Vector3d& model_point) const {
    return scale * (rotation * model_point) + translation;
  }
};

// The least-squares transform taking the columns of `model` onto the same columns of `data` (at least 3).
// Without scale this is the rigid transform of evaluate_ate.py; a reflection is never returned (the smallest
// singular direction is flipped instead). With scale it is Umeyama's similarity; throws core::InputError when
// the model points all coincide, since no scale fits them.
Alignment AlignPoints(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data, bool with_scale);

}  // namespace hoidslam::eval
