#include "hoidslam/slam/track/motion_model.h"

#include <algorithm>
#include <numbers>

#include <Eigen/Geometry>

#include "hoidslam/core/option_checks.h"

namespace hoidslam::slam {

void MotionModelOptions::Check() const {
  core::CheckNotNegative(acceleration, "Tracking.motionPriorAcceleration");
  core::CheckNotNegative(angular_acceleration_deg, "Tracking.motionPriorAngularAcceleration");
  core::CheckInRange(max_extrapolation, 1.0, 100.0, "Tracking.maxMotionExtrapolation");
}

MotionModel::MotionModel(const MotionModelOptions& options) : options_(options) { options_.Check(); }

void MotionModel::Measure(const core::Pose& T_cw_before, const core::Pose& T_cw_after, double seconds) {
  velocity_ = T_cw_after * T_cw_before.inverse();
  velocity_seconds_ = seconds;
}

core::Pose MotionModel::Predict(const core::Pose& T_cw, double elapsed) const {
  if (!velocity_) return T_cw;
  if (!(velocity_seconds_ > 0.0) || !(elapsed > 0.0)) return *velocity_ * T_cw;
  const double ratio = std::min(elapsed / velocity_seconds_, options_.max_extrapolation);
  const Eigen::AngleAxisd rotation(velocity_->linear());
  core::Pose scaled = core::Pose::Identity();
  scaled.linear() = Eigen::AngleAxisd(rotation.angle() * ratio, rotation.axis()).toRotationMatrix();
  scaled.translation() = velocity_->translation() * ratio;
  return scaled * T_cw;
}

double MotionModel::IntervalsAhead(double elapsed) const {
  if (!velocity_) return 0.0;
  return velocity_seconds_ > 0.0 ? std::clamp(elapsed / velocity_seconds_, 1.0, options_.max_extrapolation) : 1.0;
}

std::optional<PosePrior> MotionModel::Prior(const core::Pose& T_cw, double elapsed) const {
  if (!velocity_ || !(elapsed > 0.0) || options_.acceleration <= 0.0 || options_.angular_acceleration_deg <= 0.0) {
    return std::nullopt;
  }
  PosePrior prior;
  prior.T_cw = Predict(T_cw, elapsed);
  const double sigma_turn = options_.angular_acceleration_deg * std::numbers::pi / 180.0 * elapsed * elapsed;
  const double sigma_step = options_.acceleration * elapsed * elapsed;
  prior.information.diagonal() << Eigen::Vector3d::Constant(1.0 / (sigma_turn * sigma_turn)),
      Eigen::Vector3d::Constant(1.0 / (sigma_step * sigma_step));
  return prior;
}

}  // namespace hoidslam::slam
