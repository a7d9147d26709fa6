#include "hoidslam/eval/rpe.h"

#include <cmath>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/eval/association.h"

namespace hoidslam::eval {

std::string_view ToString(DeltaUnit unit) { return unit == DeltaUnit::kSeconds ? "s" : "f"; }

void RpeOptions::Check() const {
  if (!std::isfinite(delta) || delta <= 0.0)
    throw core::InputError::ForParameter("--rpe-delta", fmt::format("must be > 0, got {}", delta));
  if (delta_unit == DeltaUnit::kFrames && delta != std::floor(delta))
    throw core::InputError::ForParameter("--rpe-delta", fmt::format("must be a whole number of frames, got {}", delta));
  if (!std::isfinite(offset)) throw core::InputError::ForParameter("--offset", "must be a finite number of seconds");
}

RpeResult ComputeRpe(const core::Trajectory& groundtruth, const core::Trajectory& estimate, const RpeOptions& options) {
  options.Check();
  const core::Trajectory gt = SortedUniqueByTime(groundtruth);
  const core::Trajectory est = SortedUniqueByTime(estimate);
  if (gt.size() < 2 || est.size() < 2) {
    throw core::InputError(fmt::format("RPE needs at least 2 poses in each trajectory; the ground truth has {} and "
                                       "the estimate {}", gt.size(), est.size()));
  }
  const std::vector<double> gt_stamps = Timestamps(gt);
  const std::vector<double> est_stamps = Timestamps(est);

  std::vector<double> gt_spacing(gt_stamps.size() - 1);
  for (std::size_t k = 0; k + 1 < gt_stamps.size(); ++k) gt_spacing[k] = gt_stamps[k + 1] - gt_stamps[k];
  const double gt_max_time_difference = 2.0 * ComputeStatistics(gt_spacing).median;

  RpeResult result;
  std::vector<double> translation_errors;
  std::vector<double> rotation_errors;
  const std::size_t last = est.size() - 1;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const std::size_t j = options.delta_unit == DeltaUnit::kSeconds
                              ? ClosestIndex(est_stamps, est_stamps[i] + options.delta)
                              // Compared as doubles first: a huge --rpe-delta must not overflow the cast.
                              : (options.delta >= static_cast<double>(last - i)
                                     ? last
                                     : i + static_cast<std::size_t>(options.delta));
    if (j == last) continue;
    const double t0 = est_stamps[i] + options.offset;
    const double t1 = est_stamps[j] + options.offset;
    const std::size_t g0 = ClosestIndex(gt_stamps, t0);
    const std::size_t g1 = ClosestIndex(gt_stamps, t1);
    if (std::abs(gt_stamps[g0] - t0) > gt_max_time_difference || std::abs(gt_stamps[g1] - t1) > gt_max_time_difference)
      continue;

    const core::Pose est_motion = est[i].T_wc.inverse() * est[j].T_wc;
    const core::Pose gt_motion = gt[g0].T_wc.inverse() * gt[g1].T_wc;
    const core::Pose error = est_motion * gt_motion.inverse();
    result.pairs.push_back({est_stamps[i], est_stamps[j], gt_stamps[g0], gt_stamps[g1], error.translation().norm(),
                            core::RotationAngleDegrees(error.linear())});
    translation_errors.push_back(result.pairs.back().translation_error);
    rotation_errors.push_back(result.pairs.back().rotation_error_deg);
  }
  if (result.pairs.size() < kMinRpePairs) {
    throw core::InputError(fmt::format(
        "only {} pose pairs {} {} apart have ground truth near both ends and RPE needs {}; are the two trajectories of "
        "the same sequence, and is the estimate longer than --rpe-delta?",
        result.pairs.size(), options.delta, ToString(options.delta_unit), kMinRpePairs));
  }
  result.translation = ComputeStatistics(translation_errors);
  result.rotation_deg = ComputeStatistics(rotation_errors);
  return result;
}

}  // namespace hoidslam::eval
