#include "hoidslam/eval/alignment.h"

#include <stdexcept>

#include <Eigen/Geometry>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {

Alignment AlignPoints(const Eigen::Matrix3Xd& model, const Eigen::Matrix3Xd& data, bool with_scale) {
  if (model.cols() != data.cols() || model.cols() < 3)
    throw std::invalid_argument("AlignPoints: needs two point sets of equal size, at least 3 points");
  if (with_scale) {
    const Eigen::Matrix3Xd centred = model.colwise() - model.rowwise().mean();
    if (centred.squaredNorm() == 0.0)
      throw core::InputError("the estimated positions all coincide, so no scale can be fitted to them");
  }
  // Eigen's umeyama is the same closed form as evaluate_ate.py: SVD of the data-model cross-covariance,
  // rotation U S V^T with S = diag(1, 1, det(U) det(V)) so the result is never a reflection.
  const Eigen::Matrix4d T = Eigen::umeyama(model, data, with_scale);
  Alignment alignment;
  alignment.scale = with_scale ? T.block<3, 1>(0, 0).norm() : 1.0;
  alignment.rotation = T.block<3, 3>(0, 0) / alignment.scale;
  alignment.translation = T.block<3, 1>(0, 3);
  return alignment;
}

}  // namespace hoidslam::eval
