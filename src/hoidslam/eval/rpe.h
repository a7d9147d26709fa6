#pragma once
// Relative pose error over a fixed step, as TUM's `evaluate_rpe.py --fixed_delta` computes it, but over every
// pair instead of a random sample of at most 10000 (so the result is deterministic).

#include <string_view>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/eval/statistics.h"

namespace hoidslam::eval {

enum class DeltaUnit {
  kSeconds,  // pairs about `delta` seconds apart: with delta 1 the errors are drifts per second
  kFrames,   // pairs exactly `delta` estimated poses apart
};

std::string_view ToString(DeltaUnit unit);  // "s" or "f"

struct RpeOptions {
  double delta = 1.0;                          // --rpe-delta, > 0; a whole number when counted in frames
  DeltaUnit delta_unit = DeltaUnit::kSeconds;  // --rpe-delta-unit
  double offset = 0.0;                         // --offset, seconds, finite: added to the estimated stamps

  void Check() const;
};

// One compared pair of estimated poses (i, j) and the ground-truth poses nearest to them.
struct RpePair {
  double estimate_timestamp_0 = 0.0;
  double estimate_timestamp_1 = 0.0;
  double groundtruth_timestamp_0 = 0.0;
  double groundtruth_timestamp_1 = 0.0;
  double translation_error = 0.0;   // metres
  double rotation_error_deg = 0.0;  // degrees
};

struct RpeResult {
  ErrorStatistics translation;   // metres per delta
  ErrorStatistics rotation_deg;  // degrees per delta
  std::vector<RpePair> pairs;
};

inline constexpr std::size_t kMinRpePairs = 2;

// For each estimated pose i, j is the estimated pose nearest to t_i + delta (or i + delta frames); the pair is
// skipped when j is the last pose, or when either ground-truth pose nearest in time is more than twice the
// median ground-truth spacing away. The error of a pair is (P_i^-1 P_j) (Q_i^-1 Q_j)^-1, with P estimated and
// Q ground-truth camera-to-world poses, exactly as evaluate_rpe.py composes it. Throws InputError when fewer
// than kMinRpePairs pairs remain.
RpeResult ComputeRpe(const core::Trajectory& groundtruth, const core::Trajectory& estimate, const RpeOptions& options);

}  // namespace hoidslam::eval
