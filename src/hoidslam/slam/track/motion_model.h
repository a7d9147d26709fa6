#pragma once
// The camera's last measured motion and what it says of the next frame: a constant-velocity prediction, and how
// far a hand-held camera may depart from it in the time elapsed. Tracking searches around the prediction, holds
// each pose to it by a soft prior, and judges a pose, a relocalisation after a short loss and the frames that
// confirm it by how far they depart from it (pose_acceptance.h).

#include <optional>

#include "hoidslam/core/pose.h"
#include "hoidslam/slam/optimize/pose_optimizer.h"

namespace hoidslam::slam {

struct MotionModelOptions {
  // How far a hand-held camera's motion may depart from constant velocity in the time τ since the last frame: a
  // standard deviation of acceleration · τ² metres and angular_acceleration_deg · τ² degrees (10 mm and 1° at
  // 30 Hz; a frame dropped, four times that). Where people leave only far background in one strip of the image a
  // sideways step looks like a turn, and without the prior the pose wandered 20-110 mm within a frame there; a
  // keyframe made on such a pose moved the map for good (crowd: 70 mm ATE where other runs had 8). Where the
  // keypoints fix the pose the prior changes nothing. 0 for either: no prior (and no motion evidence).
  double acceleration = 9.0;                // m/s², Tracking.motionPriorAcceleration
  double angular_acceleration_deg = 900.0;  // °/s², Tracking.motionPriorAngularAcceleration
  // A constant velocity is continued for at most this many times the interval it was measured over: beyond
  // that it says little.
  double max_extrapolation = 4.0;

  void Check() const;
};

class MotionModel {
 public:
  MotionModel() = default;
  explicit MotionModel(const MotionModelOptions& options);

  // The camera moved from T_cw_before to T_cw_after in `seconds`.
  void Measure(const core::Pose& T_cw_before, const core::Pose& T_cw_after, double seconds);
  // Nothing measured: after a relocalisation or a long loss, the last motion says nothing of the next.
  void Reset() { velocity_.reset(); }
  bool measured() const { return velocity_.has_value(); }
  double max_extrapolation() const { return options_.max_extrapolation; }

  // Where the camera stands `elapsed` seconds after a frame at T_cw: the measured motion continued (the rotation
  // about the same axis, the translation in proportion), for at most max_extrapolation times its interval;
  // without a measured motion, where it was.
  core::Pose Predict(const core::Pose& T_cw, double elapsed) const;
  // How many measured intervals `elapsed` spans, 1 to max_extrapolation (0 without a measured motion): search
  // windows grow by it.
  double IntervalsAhead(double elapsed) const;
  // The prediction as a soft prior, as loose as MotionModelOptions says for `elapsed`; nullopt without a measured
  // motion, for elapsed <= 0, or with the prior off.
  std::optional<PosePrior> Prior(const core::Pose& T_cw, double elapsed) const;

 private:
  MotionModelOptions options_;
  std::optional<core::Pose> velocity_;  // T_cl: the last camera into the current one, over velocity_seconds_
  double velocity_seconds_ = 0.0;
};

}  // namespace hoidslam::slam
