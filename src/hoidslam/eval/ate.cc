#include "hoidslam/eval/ate.h"

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {

AteResult ComputeAte(const core::Trajectory& groundtruth, const core::Trajectory& estimate, const AteOptions& options) {
  options.Check();
  const core::Trajectory gt = SortedUniqueByTime(groundtruth);
  const core::Trajectory est = SortedUniqueByTime(estimate);
  const std::vector<Match> matches = AssociateByTimestamp(gt, est, options.association);
  if (matches.size() < kMinAteMatches) {
    throw core::InputError(fmt::format(
        "only {} of {} estimated poses match a ground-truth pose within {} s (offset {} s) and ATE needs {}; are "
        "the two trajectories of the same sequence?",
        matches.size(), est.size(), options.association.max_difference, options.association.offset, kMinAteMatches));
  }

  const auto n = static_cast<Eigen::Index>(matches.size());
  Eigen::Matrix3Xd model(3, n);
  Eigen::Matrix3Xd data(3, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Match& m = matches[static_cast<std::size_t>(k)];
    model.col(k) = est[m.second].T_wc.translation();
    data.col(k) = gt[m.first].T_wc.translation();
  }

  AteResult result;
  result.alignment = AlignPoints(model, data, options.estimate_scale);
  result.pairs.reserve(matches.size());
  std::vector<double> errors;
  errors.reserve(matches.size());
  for (Eigen::Index k = 0; k < n; ++k) {
    const Match& m = matches[static_cast<std::size_t>(k)];
    AtePair pair{gt[m.first].timestamp, est[m.second].timestamp, data.col(k), result.alignment.Apply(model.col(k))};
    pair.error = (pair.aligned_position - pair.groundtruth_position).norm();
    errors.push_back(pair.error);
    result.pairs.push_back(pair);
  }
  result.error = ComputeStatistics(errors);
  return result;
}

}  // namespace hoidslam::eval
