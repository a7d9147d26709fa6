#pragma once
// Matching the poses of two trajectories by timestamp, as TUM's associate.py does, and the nearest-stamp
// look-up that evaluate_rpe.py uses.

#include <cstddef>
#include <span>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/io/timestamp_association.h"

namespace hoidslam::eval {

// hoidslam writes stamps to the microsecond: a stamp read back is the same frame's within this.
inline constexpr double kWrittenStampTolerance = 1e-4;

struct AssociationOptions {
  double max_difference = 0.02;  // --max-difference, seconds, > 0: a pair must differ by strictly less
  double offset = 0.0;           // --offset, seconds, finite: added to the second (estimated) stamps

  void Check() const;
};

// A matched pair: indices into the first (ground truth) and second (estimate) stamp lists.
using Match = io::TimestampMatch;

// io::AssociateTimestamps (TUM's associate.py) after checking `options`; errors name the command-line flags.
std::vector<Match> AssociateByTimestamp(std::span<const double> first, std::span<const double> second,
                                        const AssociationOptions& options);
std::vector<Match> AssociateByTimestamp(const core::Trajectory& first, const core::Trajectory& second,
                                        const AssociationOptions& options);

// Index of the stamp in `sorted` (ascending, non-empty) closest to `t`; the earlier one on an exact tie.
std::size_t ClosestIndex(std::span<const double> sorted, double t);

// The trajectory as TUM's tools see it (they key poses by stamp): sorted by time, and of poses with equal
// stamps only the last one kept. Throws InputError for a timestamp that is not finite.
core::Trajectory SortedUniqueByTime(core::Trajectory trajectory);

std::vector<double> Timestamps(const core::Trajectory& trajectory);

}  // namespace hoidslam::eval
