#include "hoidslam/eval/ate.h"

#include <array>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {

namespace {

// The pairs of poses ATE is computed on; InputError when too few match.
std::vector<Match> MatchForAte(const core::Trajectory& gt, const core::Trajectory& est,
                               const AssociationOptions& association) {
  std::vector<Match> matches = AssociateByTimestamp(gt, est, association);
  if (matches.size() < kMinAteMatches) {
    throw core::InputError(fmt::format(
        "only {} of {} estimated poses match a ground-truth pose within {} s (offset {} s) and ATE needs {}; are "
        "the two trajectories of the same sequence?",
        matches.size(), est.size(), association.max_difference, association.offset, kMinAteMatches));
  }
  return matches;
}

}  // namespace

AteResult ComputeAte(const core::Trajectory& groundtruth, const core::Trajectory& estimate, const AteOptions& options) {
  options.Check();
  const core::Trajectory gt = SortedUniqueByTime(groundtruth);
  const core::Trajectory est = SortedUniqueByTime(estimate);
  const std::vector<Match> matches = MatchForAte(gt, est, options.association);

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

Alignment AlignPoses(const core::Trajectory& groundtruth, const core::Trajectory& estimate,
                     const AssociationOptions& association, double lever) {
  association.Check();
  if (!(lever > 0.0)) throw core::InputError(fmt::format("a pose alignment's lever must be > 0 m, not {}", lever));
  const core::Trajectory gt = SortedUniqueByTime(groundtruth);
  const core::Trajectory est = SortedUniqueByTime(estimate);
  const std::vector<Match> matches = MatchForAte(gt, est, association);
  const std::array<Eigen::Vector3d, 4> in_camera{Eigen::Vector3d::Zero(), lever * Eigen::Vector3d::UnitX(),
                                                 lever * Eigen::Vector3d::UnitY(), lever * Eigen::Vector3d::UnitZ()};
  const auto n = static_cast<Eigen::Index>(matches.size() * in_camera.size());
  Eigen::Matrix3Xd model(3, n);
  Eigen::Matrix3Xd data(3, n);
  Eigen::Index column = 0;
  for (const Match& m : matches) {
    for (const Eigen::Vector3d& point : in_camera) {
      model.col(column) = est[m.second].T_wc * point;
      data.col(column) = gt[m.first].T_wc * point;
      ++column;
    }
  }
  return AlignPoints(model, data, /*with_scale=*/false);
}

}  // namespace hoidslam::eval
