#include "hoidslam/eval/association.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {

void AssociationOptions::Check() const {
  if (!std::isfinite(max_difference) || max_difference <= 0.0)
    throw core::InputError::ForParameter("--max-difference", fmt::format("must be > 0 seconds, got {}", max_difference));
  if (!std::isfinite(offset)) throw core::InputError::ForParameter("--offset", "must be a finite number of seconds");
}

std::vector<Match> AssociateByTimestamp(std::span<const double> first, std::span<const double> second,
                                        const AssociationOptions& options) {
  options.Check();
  return io::AssociateTimestamps(first, second, options.max_difference, options.offset, "--max-difference");
}

std::vector<Match> AssociateByTimestamp(const core::Trajectory& first, const core::Trajectory& second,
                                        const AssociationOptions& options) {
  return AssociateByTimestamp(Timestamps(first), Timestamps(second), options);
}

std::size_t ClosestIndex(std::span<const double> sorted, double t) {
  if (sorted.empty()) throw std::invalid_argument("ClosestIndex: empty list");
  const auto after = std::lower_bound(sorted.begin(), sorted.end(), t);
  if (after == sorted.begin()) return 0;
  const auto index = static_cast<std::size_t>(after - sorted.begin());
  if (after == sorted.end()) return index - 1;
  return t - sorted[index - 1] <= *after - t ? index - 1 : index;
}

core::Trajectory SortedUniqueByTime(core::Trajectory trajectory) {
  for (const core::StampedPose& pose : trajectory)
    if (!std::isfinite(pose.timestamp)) throw core::InputError("a trajectory has a timestamp that is not a number");
  std::stable_sort(trajectory.begin(), trajectory.end(),
                   [](const core::StampedPose& l, const core::StampedPose& r) { return l.timestamp < r.timestamp; });
  // Keep the last of each run of equal stamps: walk backwards keeping first occurrences, then restore order.
  std::reverse(trajectory.begin(), trajectory.end());
  const auto end = std::unique(trajectory.begin(), trajectory.end(), [](const auto& l, const auto& r) {
    return l.timestamp == r.timestamp;
  });
  trajectory.erase(end, trajectory.end());
  std::reverse(trajectory.begin(), trajectory.end());
  return trajectory;
}

std::vector<double> Timestamps(const core::Trajectory& trajectory) {
  std::vector<double> stamps(trajectory.size());
  std::transform(trajectory.begin(), trajectory.end(), stamps.begin(),
                 [](const core::StampedPose& p) { return p.timestamp; });
  return stamps;
}

}  // namespace hoidslam::eval
