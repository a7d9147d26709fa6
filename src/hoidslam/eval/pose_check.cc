#include "hoidslam/eval/pose_check.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

namespace hoidslam::eval {
std::size_t PoseCheck::Wrong() const {
  return static_cast<std::size_t>(std::count_if(poses.begin(), poses.end(), [](const CheckedPose& p) {
    return p.wrong;
  }));
}

PoseCheck CheckPoses(const core::Trajectory& groundtruth, const core::Trajectory& estimate,
                     const Alignment& alignment, std::span<const double> stamps,
                     const AssociationOptions& association, const PoseCheckOptions& options) {
  association.Check();
  const core::Trajectory gt = SortedUniqueByTime(groundtruth);
  const core::Trajectory est = SortedUniqueByTime(estimate);
  const std::vector<double> gt_stamps = Timestamps(gt);
  const std::vector<double> est_stamps = Timestamps(est);
  PoseCheck check;
  for (const double stamp : stamps) {
    if (est.empty() || gt.empty()) {
      ++check.unmatched;
      continue;
    }
    const core::StampedPose& pose = est[ClosestIndex(est_stamps, stamp)];
    const core::StampedPose& truth = gt[ClosestIndex(gt_stamps, pose.timestamp + association.offset)];
    if (std::abs(pose.timestamp - stamp) > kWrittenStampTolerance ||
        !(std::abs(truth.timestamp - (pose.timestamp + association.offset)) < association.max_difference)) {
      ++check.unmatched;
      continue;
    }
    CheckedPose checked;
    checked.timestamp = pose.timestamp;
    checked.position_error = (alignment.Apply(pose.T_wc.translation()) - truth.T_wc.translation()).norm();
    const Eigen::Matrix3d difference = truth.T_wc.linear().transpose() * alignment.rotation * pose.T_wc.linear();
    checked.rotation_error_deg = core::RotationAngleDegrees(difference);
    checked.wrong = checked.position_error > options.max_position_error ||
                    checked.rotation_error_deg > options.max_rotation_error_deg;
    check.poses.push_back(checked);
  }
  return check;
}

PoseCheck CheckRelativePoses(const core::Trajectory& groundtruth, std::span<const RelativePose> relative,
                             const AssociationOptions& association, const PoseCheckOptions& options) {
  association.Check();
  const core::Trajectory gt = SortedUniqueByTime(groundtruth);
  const std::vector<double> gt_stamps = Timestamps(gt);
  const auto truth_at = [&](double stamp) -> const core::StampedPose* {
    if (gt.empty()) return nullptr;
    const core::StampedPose& truth = gt[ClosestIndex(gt_stamps, stamp + association.offset)];
    return std::abs(truth.timestamp - (stamp + association.offset)) < association.max_difference ? &truth : nullptr;
  };
  PoseCheck check;
  for (const RelativePose& r : relative) {
    const core::StampedPose* frame = truth_at(r.timestamp);
    const core::StampedPose* base = truth_at(r.base_timestamp);
    if (frame == nullptr || base == nullptr) {
      ++check.unmatched;
      continue;
    }
    const core::Pose T_true = base->T_wc.inverse() * frame->T_wc;
    const core::Pose difference = T_true.inverse() * r.T_base_frame;
    CheckedPose checked;
    checked.timestamp = r.timestamp;
    checked.position_error = difference.translation().norm();
    checked.rotation_error_deg = core::RotationAngleDegrees(difference.linear());
    checked.wrong = checked.position_error > options.max_position_error ||
                    checked.rotation_error_deg > options.max_rotation_error_deg;
    check.poses.push_back(checked);
  }
  return check;
}

nlohmann::json PoseCheckToJson(const PoseCheck& check, const PoseCheckOptions& options) {
  nlohmann::json poses = nlohmann::json::array();
  for (const CheckedPose& p : check.poses) {
    poses.push_back({{"timestamp", p.timestamp},
                     {"position_error_m", p.position_error},
                     {"rotation_error_deg", p.rotation_error_deg},
                     {"false", p.wrong}});
  }
  return {{"count", check.poses.size()},
          {"false", check.Wrong()},
          {"unmatched", check.unmatched},
          {"max_position_error_m", options.max_position_error},
          {"max_rotation_error_deg", options.max_rotation_error_deg},
          {"poses", std::move(poses)}};
}

}  // namespace hoidslam::eval
