#pragma once
// Local bundle adjustment with Ceres: keyframe poses and map point positions refined together from their
// keypoint observations (ORB-SLAM's LocalBundleAdjustment, on plain data so it can be tested on its own and run
// without the map's lock held).

#include <atomic>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/core/pose.h"
#include "hoidslam/slam/data/measurement.h"

namespace hoidslam::slam {

struct BundleAdjustmentProblem {
  RgbdCamera camera;
  std::vector<core::Pose> T_cw;            // one per keyframe, world to camera
  std::vector<std::uint8_t> pose_fixed;    // one per keyframe: 1 = held constant (at least one must be)
  std::vector<Eigen::Vector3d> points_w;   // map points, world coordinates
  struct Observation {
    int keyframe = 0;  // index into T_cw
    int point = 0;     // index into points_w
    KeypointMeasurement measurement;
  };
  std::vector<Observation> observations;
};

struct BundleAdjustmentOptions {
  int first_iterations = 5;    // with a Huber kernel, all observations
  int second_iterations = 10;  // without a kernel, after leaving out the outliers of the first pass; 0 skips it
  double chi2_mono = kChi2Mono;
  double chi2_stereo = kChi2Stereo;
  int num_threads = 1;         // Ceres threads; 1 gives identical results run after run
  // The reduced keyframe system solved as a sparse matrix: for a global adjustment, where most keyframe pairs share
  // no point; a local one's is small and dense.
  bool sparse = false;
};

struct BundleAdjustmentResult {
  // One per observation: 1 when its χ² error after the last pass exceeds the threshold or the point lies behind
  // that camera; the caller removes these observations from the map.
  std::vector<std::uint8_t> outlier;
  bool aborted = false;  // stopped early because *stop became true (the problem holds the state reached)
  int iterations = 0;    // Ceres iterations run, both passes together
};

// Refines problem.T_cw (of the keyframes not fixed) and problem.points_w in place. ORB-SLAM's two passes:
// `first_iterations` with a Huber kernel (δ = sqrt(threshold)), then observations whose χ² error exceeds the
// threshold (or whose point is behind the camera) are left out, and `second_iterations` more run without a
// kernel. `stop`, when given, is polled between iterations: when it becomes true the adjustment ends early.
// Keyframes and points without observations are left untouched. Throws std::invalid_argument for indices out of
// range, a pose_fixed of the wrong size or when no pose is fixed. Points are eliminated first (Ceres DENSE_SCHUR,
// or SPARSE_SCHUR with options.sparse: the reduced keyframe system of a local BA is small, and dense beat sparse
// there).
BundleAdjustmentResult RunBundleAdjustment(BundleAdjustmentProblem& problem, const BundleAdjustmentOptions& options = {},
                                           const std::atomic<bool>* stop = nullptr);

}  // namespace hoidslam::slam
