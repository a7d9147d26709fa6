#pragma once
// Absolute trajectory error, as TUM's evaluate_ate.py computes it: associate the stamps, align the estimated
// positions to the ground-truth ones (rigidly unless asked for scale), and measure each matched pair's
// remaining position difference.

#include <vector>

#include <Eigen/Core>

#include "hoidslam/core/pose.h"
#include "hoidslam/eval/alignment.h"
#include "hoidslam/eval/association.h"
#include "hoidslam/eval/statistics.h"

namespace hoidslam::eval {

struct AteOptions {
  AssociationOptions association{};
  bool estimate_scale = false;  // --scale: similarity (Sim(3)) alignment, for estimates of unknown scale

  void Check() const { association.Check(); }
};

// One matched pose pair, kept for plots.
struct AtePair {
  double groundtruth_timestamp = 0.0;
  double estimate_timestamp = 0.0;
  Eigen::Vector3d groundtruth_position = Eigen::Vector3d::Zero();
  Eigen::Vector3d aligned_position = Eigen::Vector3d::Zero();  // the estimated position after alignment
  double error = 0.0;                                          // metres: |aligned - groundtruth|
};

struct AteResult {
  ErrorStatistics error;  // metres, over all matched pairs (error.count of them)
  Alignment alignment;    // takes estimated positions into the ground-truth frame
  std::vector<AtePair> pairs;
};

inline constexpr std::size_t kMinAteMatches = 3;

// Throws InputError when fewer than kMinAteMatches stamps match (the trajectories are probably of different
// sequences, or need an --offset).
AteResult ComputeAte(const core::Trajectory& groundtruth, const core::Trajectory& estimate, const AteOptions& options);

// The rigid transform that best takes the estimated camera poses — centres and orientations — onto the ground
// truth's: each matched pose stands for its centre and the three points `lever` metres along its axes, aligned as
// ComputeAte aligns centres. ComputeAte's alignment knows orientation only through the positions' spread, and a
// short or straight path leaves it a few tenths of a degree free: nothing for the ATE, centimetres at the far wall of
// a map drawn in that frame. Pick `lever` at the depth the map's surfaces are seen from. Throws InputError as
// ComputeAte does.
Alignment AlignPoses(const core::Trajectory& groundtruth, const core::Trajectory& estimate,
                     const AssociationOptions& association, double lever);

}  // namespace hoidslam::eval
