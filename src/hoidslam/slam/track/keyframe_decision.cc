#include "hoidslam/slam/track/keyframe_decision.h"

#include "hoidslam/core/option_checks.h"

namespace hoidslam::slam {

void KeyFrameDecisionOptions::Check() const {
  core::CheckPositive(max_interval, "Tracking.keyFrameMaxInterval");
  core::CheckShare(reference_ratio, "Tracking.keyFrameReferenceRatio");
  core::CheckShare(reference_ratio_first, "Tracking.keyFrameReferenceRatioFirst");
  core::CheckShare(weak_ratio, "Tracking.keyFrameWeakRatio");
  core::CheckNotNegative(close_tracked, "Tracking.keyFrameCloseTracked");
  core::CheckNotNegative(close_untracked, "Tracking.keyFrameCloseUntracked");
  core::CheckNotNegative(min_inliers, "Tracking.keyFrameMinInliers");
  core::CheckPositive(max_queued, "Tracking.keyFrameMaxQueued");
}

bool NeedNewKeyFrame(const KeyFrameDecisionInput& input, const KeyFrameDecisionOptions& options) {
  if (input.mapper_paused) return false;
  // Tiny epsilon: frame stamps at an exact rate land a hair short of the interval they span.
  constexpr double kEpsilon = 1e-6;
  const bool need_close =
      input.close_tracked < options.close_tracked && input.close_untracked > options.close_untracked;
  const double reference_ratio = input.map_keyframes < 2 ? options.reference_ratio_first : options.reference_ratio;
  const bool interval_passed = input.since_keyframe + kEpsilon >= options.max_interval;
  const bool weak = input.inliers < options.weak_ratio * input.reference_points || need_close;
  const bool fewer_than_reference =
      (input.inliers < reference_ratio * input.reference_points || need_close) && input.inliers > options.min_inliers;
  if (!((interval_passed || input.mapper_idle || weak) && fewer_than_reference)) return false;
  return input.mapper_idle || input.mapper_queued < options.max_queued;
}

}  // namespace hoidslam::slam
